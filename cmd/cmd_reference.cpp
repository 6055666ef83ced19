// `aoeval reference --scene S [--view V] [--res WxH] [--spp N] [--weighting cosine|uniform]
//  [--dmax D] [--falloff none|linear|sqrt|exp|power:K] [--sampler random|stratified|sobol]
//  [--seed K] [--normal shading|geometric] [--target-stderr E [--max-spp M]] [--frame K]
//  [--no-cache] -o FILE.exr`
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "base/errors.h"
#include "base/text_files.h"
#include "base/version.h"
#include "cmd/commands.h"
#include "references/cache_lock.h"
#include "references/reference_cache.h"
#include "scenes/corpus.h"
#include "scenes/gbuffer.h"
#include "scenes/sequence_frame.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

struct Options {
  std::string scene, view, res, output;
  // Defaults: ReferenceSettings' (references/reference.h), declared there once.
  int spp = ReferenceSettings{}.spp;
  std::string weighting = "cosine", dmax = "inf", falloff = "none";
  std::string sampler = sampler_name(ReferenceSettings{}.sampler);
  std::string normal = "shading";
  uint64_t seed = ReferenceSettings{}.seed;
  double target_stderr = ReferenceSettings{}.target_stderr;
  int max_spp = ReferenceSettings{}.max_spp;
  bool no_cache = false;
  int frame = 0;
};

void copy_atomically(const std::string& from, const std::string& to) {
  const std::string tmp = temporary_path_for(to);
  fs::copy_file(from, tmp, fs::copy_options::overwrite_existing);
  commit_temporary(tmp, to);
}

void run_reference(const Options& o) {
  const auto t0 = std::chrono::steady_clock::now();
  install_interrupt_cleanup();  // Ctrl-C leaves no temporary (text_files.h)
  remove_dead_temporaries_of(o.output);
  const auto [w, h] = parse_resolution(o.res);
  ReferenceSettings s;
  s.spp = o.spp;
  s.seed = o.seed;
  s.target_stderr = o.target_stderr;
  s.max_spp = o.max_spp;
  parse_reference_options(s, o.weighting, o.dmax, o.falloff, o.sampler, o.normal);
  if (!std::isfinite(s.target_stderr) || s.target_stderr < 0.0)
    throw InputError("--target-stderr: must be a finite positive number");
  if (s.target_stderr > 0.0 && s.max_spp < s.spp)
    throw InputError("--max-spp: must be at least --spp");
  const Scene base = load_scene(o.scene);
  const View& view = base.view(o.view);
  // Frame k (CONTRACT §10): its posed geometry and camera key the cache, and its seed is seed + k.
  const SequenceFrame frame = sequence_frame(base, view, o.frame);
  std::optional<Scene> posed;
  if (frame.moves_objects) posed = posed_scene(base, frame);
  const Scene& scene = posed ? *posed : base;
  const Camera camera = frame_camera(frame, w, h);
  // A frame that poses what the frame before it did has that frame's reference (seed + j, j the
  // first frame of the unchanged run; issue 42), so it is one cache entry.
  if (view.sequence) s = frame_reference_settings(s, unchanged_since(base, view, o.frame));
  const std::string key = reference_cache_key(scene, camera, s);
  const std::string cached = reference_cache_path(key);
  auto served = [&] {
    std::fprintf(stderr, "reference: served from cache %s (%.2f s)\n", cached.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  };
  if (!o.no_cache && usable_cache_entry(cached, key)) {
    copy_atomically(cached, o.output);
    served();
    return;
  }
  std::optional<ReferenceImage> computed;
  auto compute = [&] {
    EmbreeScene es(scene);
    const GBuffer g = render_gbuffer(es, camera);
    computed = compute_reference(es, g, s);
    const OIIO::ImageBuf image = reference_to_image(*computed, s.target_stderr > 0.0);
    Attributes attributes = reference_attributes(scene, view, camera, s);
    if (view.sequence) attributes.emplace_back("aoeval:frame", std::to_string(o.frame));
    add_cache_attributes(attributes, key, image);
    // Written once and copied, so the output and the cached file are the same bytes (the EXR
    // header's capDate included) and a later cache hit serves exactly this file.
    write_exr(o.output, image, attributes);
    if (!o.no_cache) copy_atomically(o.output, cached);
  };
  if (o.no_cache) {
    compute();
  } else if (!fill_cache_entry_once(
                 cached, [&] { return usable_cache_entry(cached, key); }, compute)) {
    // Another process computed it while this one waited on the entry's lock (cache_lock.h).
    copy_atomically(cached, o.output);
    served();
    return;
  }
  const ReferenceImage& r = *computed;
  double se2 = 0.0;
  size_t covered = 0;
  for (size_t k = 0; k < r.ao.size(); ++k) {
    if (!r.covered(k)) continue;
    se2 += static_cast<double>(r.stderr_ao[k]) * r.stderr_ao[k];
    ++covered;
  }
  std::fprintf(stderr,
               "reference: %dx%d, %.1f Mrays traced in %.2f s (%.2f Mrays/s), rms stderr %.4f%s\n",
               r.width, r.height, r.rays_traced / 1e6, r.seconds, r.rays_traced / 1e6 / r.seconds,
               covered ? std::sqrt(se2 / covered) : 0.0, o.no_cache ? "" : ", cached");
}

}  // namespace

void add_reference_command(CLI::App& app) {
  static Options o;
  auto* cmd =
      app.add_subcommand("reference", "ground-truth AO with Embree, with its standard error");
  cmd->add_option("--scene", o.scene, "corpus name or scene file")->required();
  cmd->add_option("--view", o.view, "view name (default: the scene's first view)");
  cmd->add_option("--res", o.res, "resolution WIDTHxHEIGHT (default: the view's)");
  cmd->add_option("--spp", o.spp, "rays per pixel (the minimum with --target-stderr)")
      ->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--weighting", o.weighting, "cosine or uniform");
  cmd->add_option("--dmax", o.dmax, "occluder range in scene units, or inf");
  cmd->add_option("--falloff", o.falloff,
                  "none, linear, sqrt, exp or power:K (rho(x) = x^K, K > 0) (CONTRACT §3)");
  cmd->add_option("--sampler", o.sampler, "random, stratified or sobol");
  // CLI11 reads "-1" into an unsigned as 2^64 - 1; a seed is a plain non-negative integer.
  cmd->add_option("--seed", o.seed, "random seed (a non-negative integer)")
      ->check(CLI::Validator(
          [](std::string& text) {
            return !text.empty() && text.size() <= 20 &&
                           text.find_first_not_of("0123456789") == std::string::npos
                       ? std::string()
                       : "must be a non-negative integer, got '" + text + "'";
          },
          "UINT"));
  cmd->add_option("--normal", o.normal, "hemisphere orientation: shading or geometric");
  cmd->add_option("--target-stderr", o.target_stderr,
                  "keep sampling each pixel until its standard error is <= this");
  cmd->add_option("--max-spp", o.max_spp, "ray limit per pixel with --target-stderr")
      ->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--frame", o.frame,
                  "frame K of a sequence view (CONTRACT §10; traced with seed + K)")
      ->check(frame_number_check());
  cmd->add_flag("--no-cache", o.no_cache, "neither read nor write the reference cache");
  cmd->add_option("-o,--output", o.output, "output OpenEXR file")->required();
  cmd->callback([] { run_reference(o); });
}

}  // namespace aoeval
