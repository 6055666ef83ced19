// `aoeval compare REF.exr EST.exr [--json FILE] [--errmap FILE.png] [--signed FILE.png]
//  [--mosaic FILE.png] [--true-ref TRUE.exr]`: metrics over the pixels both images cover, and maps.
// `aoeval compare --sequence REFDIR ESTDIR (--motion GBUFDIR | --static) [--json FILE]`: the
// sequence keys of CONTRACT §10 over two frame folders (compare_sequence.h).
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/json_reader.h"
#include "cmd/commands.h"
#include "cmd/compare_sequence.h"
#include "drawing/error_maps.h"
#include "harness/scoring/bent_metrics.h"
#include "harness/scoring/metrics.h"
#include "scenes/ao_exr.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace {

void check_same_view(const AoExr& a, const AoExr& b) {
  if (a.width != b.width || a.height != b.height)
    throw InputError(b.path + ": size " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                     " differs from " + a.path + " (" + std::to_string(a.width) + "x" +
                     std::to_string(a.height) + ")");
  if (!a.scene.empty() && !b.scene.empty() && (a.scene != b.scene || a.view != b.view))
    throw InputError(b.path + ": aoeval:scene/view " + b.scene + "/" + b.view + " differ from " +
                     a.path + " (" + a.scene + "/" + a.view + ")");
}

std::vector<uint8_t> joint_mask(const AoExr& a, const AoExr& b) {
  std::vector<uint8_t> m(a.ao.size());
  for (size_t k = 0; k < m.size(); ++k) m[k] = a.covered(k) && b.covered(k);
  return m;
}

// An image output whose format OpenImageIO cannot write is bad usage, found before any work.
void check_image_output(const std::string& path, const char* option) {
  if (path.empty()) return;
  auto writer = OIIO::ImageOutput::create(path);
  if (!writer)
    throw InputError(std::string(option) + " " + path + ": no image format for the extension '" +
                     std::filesystem::path(path).extension().string() + "' (use .png or .exr)");
}

// The outputs of one compare: on failure every file it already wrote is removed again, so a
// failed command leaves nothing (CONTRACT §2).
class OutputSet {
 public:
  ~OutputSet() {
    if (committed_) return;
    std::error_code ec;
    for (const auto& p : written_) std::filesystem::remove(p, ec);
  }
  void wrote(const std::string& path) { written_.push_back(path); }
  void commit() { committed_ = true; }

 private:
  std::vector<std::string> written_;
  bool committed_ = false;
};

}  // namespace

void add_compare_command(CLI::App& app) {
  struct Options {
    std::string ref, est, json, errmap, signed_map, mosaic, true_ref, motion;
    bool sequence = false, assume_static = false;
  };
  static Options o;
  auto* cmd =
      app.add_subcommand("compare", "metrics and error maps of an estimate against a reference");
  cmd->add_option("REF", o.ref,
                  "reference EXR (channels AO, A, optional AO_stderr, bent.X/Y/Z, bent_stderr); "
                  "with --sequence a folder of them")
      ->required();
  cmd->add_option("EST", o.est,
                  "estimate EXR (channels AO, A, optional bent.X/Y/Z); with --sequence a folder")
      ->required();
  cmd->add_option("--json", o.json, "write the metrics as JSON to this file (else to stdout)");
  cmd->add_option("--errmap", o.errmap, "absolute-error map (PNG)");
  cmd->add_option("--signed", o.signed_map, "signed-error map (PNG)");
  cmd->add_option("--mosaic", o.mosaic, "reference | estimate | |error| | signed error (PNG)");
  cmd->add_option("--true-ref", o.true_ref, "unbounded cosine reference: adds true_* metrics");
  cmd->add_flag("--sequence", o.sequence,
                "REF and EST are frame folders, each frame_0000.exr, frame_0001.exr, ... with no "
                "gaps (references; estimates): prints the sequence keys of CONTRACT §10 and "
                "rmse_excess_by_frame");
  cmd->add_option("--motion", o.motion,
                  "with --sequence: folder of the frames' G-buffers, frame_KKKK.exr from `aoeval "
                  "gbuffer --frame K` (motion.X/Y, disoccluded)");
  cmd->add_flag("--static", o.assume_static,
                "with --sequence, instead of --motion: nothing moves (zero motion, nothing "
                "disoccluded)");
  cmd->callback([] {
    if (!o.sequence && (!o.motion.empty() || o.assume_static))
      throw InputError(std::string(o.assume_static ? "--static" : "--motion") +
                       " needs --sequence");
    if (o.sequence) {
      for (const auto& [value, name] : {std::pair{o.errmap, "--errmap"},
                                        {o.signed_map, "--signed"},
                                        {o.mosaic, "--mosaic"},
                                        {o.true_ref, "--true-ref"}})
        if (!value.empty()) throw InputError(std::string(name) + " does not go with --sequence");
      const nlohmann::json out = compare_sequence({o.ref, o.est, o.motion, o.assume_static});
      if (o.json.empty())
        std::printf("%s\n", out.dump(2).c_str());
      else
        write_text(o.json, out.dump(2) + "\n");
      return;
    }
    check_image_output(o.errmap, "--errmap");
    check_image_output(o.signed_map, "--signed");
    check_image_output(o.mosaic, "--mosaic");
    const AoExr ref = read_ao_exr(o.ref), est = read_ao_exr(o.est);
    check_same_view(ref, est);
    if (!ref.definition.empty() && !est.definition.empty() &&
        parse_json_text(ref.definition, o.ref + ": aoeval:definition") !=
            parse_json_text(est.definition, o.est + ": aoeval:definition"))
      std::fprintf(stderr, "aoeval: note: the estimate's definition %s is not the reference's %s\n",
                   est.definition.c_str(), ref.definition.c_str());
    const auto mask = joint_mask(ref, est);
    const Metrics m = compare_images({ref.width, ref.height, ref.ao.data()},
                                     {est.width, est.height, est.ao.data()}, mask, ref.stderr_ao);
    nlohmann::json out = to_json(m);
    // Bent-normal metrics (bent_metrics.h) where both images carry bent.X/Y/Z.
    auto add_bent = [&](const AoExr& r, const std::vector<uint8_t>& joint,
                        const std::string& prefix) {
      if (r.bent.empty() || est.bent.empty()) return;
      if (const auto b = compare_bent(r.width, r.height, r.bent, est.bent, joint, r.bent_stderr))
        add_bent_json(*b, out, prefix);
    };
    add_bent(ref, mask, "");
    if (!o.true_ref.empty()) {
      const AoExr truth = read_ao_exr(o.true_ref);
      check_same_view(truth, est);
      const std::vector<uint8_t> joint = joint_mask(truth, est);
      const Metrics t =
          compare_images({truth.width, truth.height, truth.ao.data()},
                         {est.width, est.height, est.ao.data()}, joint, truth.stderr_ao);
      out.update(to_json(t, "true_"));
      add_bent(truth, joint, "true_");
    }
    const int w = ref.width, h = ref.height;
    OutputSet outputs;
    if (!o.errmap.empty()) {
      write_image(o.errmap, abs_error_map(w, h, ref.ao.data(), est.ao.data(), mask, 0.0f));
      outputs.wrote(o.errmap);
    }
    if (!o.signed_map.empty()) {
      write_image(o.signed_map, signed_error_map(w, h, ref.ao.data(), est.ao.data(), mask, 0.0f));
      outputs.wrote(o.signed_map);
    }
    if (!o.mosaic.empty()) {
      char caption[256];
      std::snprintf(caption, sizeof(caption), "%s/%s %dx%d   rmse %.4f   ssim %.3f   flip %.3f",
                    ref.scene.c_str(), ref.view.c_str(), w, h, m.rmse, m.ssim, m.flip_mean);
      write_image(o.mosaic, error_mosaic(w, h, ref.ao.data(), est.ao.data(), mask, caption));
      outputs.wrote(o.mosaic);
    }
    if (o.json.empty())
      std::printf("%s\n", out.dump(2).c_str());
    else
      write_text(o.json, out.dump(2) + "\n");
    outputs.commit();
  });
}

}  // namespace aoeval
