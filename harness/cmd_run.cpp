// `aoeval run [--suite default|quick|paper] [--out DIR]`: the main job. At this stage of the
// project the suite renders every scene's shared G-buffer for each of its views and writes the HTML
// gallery (reports/gbuffer_gallery); references and estimators join it as they land.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "corpus.h"
#include "errors.h"
#include "gbuffer.h"
#include "progress.h"
#include "reports/gbuffer_gallery.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> suite_scenes(const std::string& suite) {
  if (suite == "quick") return {"sphere-uniform", "cornell-box", "bunny"};
  return corpus_names();  // default and paper: the whole corpus
}

void run_suite(const std::string& suite, const std::string& out_dir) {
  const auto names = suite_scenes(suite);
  // paper renders at twice the views' resolution; quick and default at the views' own.
  const int scale = suite == "paper" ? 2 : 1;
  std::vector<GalleryEntry> entries;
  Progress progress("run " + suite, names.size());
  for (const auto& name : names) {
    const auto t0 = std::chrono::steady_clock::now();
    Scene scene = load_scene(name);
    const double load_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EmbreeScene es(scene);
    for (const auto& view : scene.views) {
      const Camera camera = make_camera(view, view.width * scale, view.height * scale);
      GBuffer g = render_gbuffer(es, camera);
      GalleryEntry e;
      e.scene = scene.name;
      e.view = view.name;
      e.triangles = scene.triangle_count();
      e.objects = scene.objects.size();
      e.load_ms = load_ms;
      e.bvh_ms = es.build_ms();
      e.gbuffer_exr = (fs::path("scenes") / scene.name / (view.name + "_gbuffer.exr")).string();
      write_exr((fs::path(out_dir) / e.gbuffer_exr).string(), gbuffer_to_image(g),
                gbuffer_attributes(scene, view, camera));
      entries.push_back(e);
    }
    progress.step(name);
  }
  const std::string page = write_gbuffer_gallery(out_dir, suite, entries);
  std::printf("%s\n", page.c_str());
}

}  // namespace

void add_run_command(CLI::App& app) {
  static std::string suite = "default";
  static std::string out;
  auto* cmd = app.add_subcommand("run", "run a suite and write its HTML report");
  cmd->add_option("--suite", suite, "quick, default or paper")
      ->check(CLI::IsMember({"quick", "default", "paper"}));
  cmd->add_option("--out", out, "output folder (default: out/SUITE)");
  cmd->callback([] { run_suite(suite, out.empty() ? "out/" + suite : out); });
}

}  // namespace aoeval
