#include "cmd/bench_plugins.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/resolution.h"
#include "base/summary.h"
#include "estimators/plugins/plugin_registry.h"
#include "estimators/registry.h"
#include "estimators/vulkan/vk_context.h"
#include "scenes/corpus.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

struct Timing {
  std::string name, note;
  double wall_ms = 0.0;  // median wall time of one run() call
  double own_ms = -1.0;  // median of the estimator's own time (GPU span, frame_ms), -1 = none
  double frames = 1.0;   // frames one run() computes
  std::string skipped;
};

Timing time_estimator(const std::string& name, const std::string& note, Estimator& e,
                      const EstimateContext& context, const PluginBenchOptions& o,
                      double frames = 1.0) {
  Timing t;
  t.name = name;
  t.note = note;
  t.frames = frames;
  std::vector<double> wall, own;
  try {
    e.prepare(context);
    for (int i = 0; i < o.warmup; ++i) e.run(context);
    for (int i = 0; i < o.repetitions; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      const EstimateResult r = e.run(context);
      wall.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      // A GPU span, or a plug-in's own frame time (the median of its frames).
      const auto total = r.pass_ms.find("total_ms");
      if (total != r.pass_ms.end() && r.timing_source != "process-wall")
        own.push_back(total->second);
    }
  } catch (const EstimatorUnavailable& u) {
    t.skipped = u.what();
    return t;
  }
  t.wall_ms = median(wall);
  if (!own.empty()) t.own_ms = median(own);
  return t;
}

std::unique_ptr<Estimator> create(const EstimatorInfo& info, const nlohmann::json& overrides) {
  return info.create(resolve_params(info.name, info.params, overrides, "bench plugins"));
}

std::string fixed(double v, int digits = 2) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  return buf;
}

}  // namespace

void bench_plugins(const PluginBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  Scene scene = load_scene(o.scene);
  const View& view = scene.view(o.view);
  EmbreeScene es(scene);
  const GBuffer g = render_gbuffer(es, make_camera(view, w, h));
  const EstimateContext context{scene, es, g};

  // Scratch plug-ins, removed at the end.
  std::string pattern = (fs::temp_directory_path() / "aoeval-bench-plugins-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a folder " + pattern);
  const fs::path scratch = pattern;
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  } cleanup{scratch};
  fs::create_directories(scratch / "copy");
  write_text((scratch / "copy" / "estimator.json").string(),
             R"({"name": "bench-copy", "summary": "cp of a constant AO.exr", "kind": "process",
                 "command": ["/bin/sh", "copy.sh"], "definition": {"weighting": "cosine"}})");
  write_text((scratch / "copy" / "copy.sh").string(), "exec cp constant.exr \"$6\"\n");
  {
    EstimateResult one;
    one.ao.assign(g.pixel_count(), 1.0f);
    OIIO::ImageBuf image(OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::FLOAT));
    std::fill_n(static_cast<float*>(image.localpixels()), g.pixel_count(), 1.0f);
    image.specmod().channelnames = {"AO"};
    write_exr((scratch / "copy" / "constant.exr").string(), image, {});
  }
  fs::create_directories(scratch / "null");
  write_text((scratch / "null" / "estimator.json").string(),
             R"({"name": "bench-null", "summary": "stores 1", "kind": "glsl",
                 "shaders": ["null.comp"], "definition": {"weighting": "cosine"}})");
  write_text((scratch / "null" / "null.comp").string(),
             "#version 450\nlayout(local_size_x = 8, local_size_y = 8) in;\nvoid main() {\n"
             "  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
             "  if (aoeval_inside(p)) imageStore(aoeval_out, p, vec4(1.0));\n}\n");

  std::vector<Timing> process, glsl;
  {
    auto e = create(find_estimator("constant"), {});
    process.push_back(time_estimator("constant", "built-in, in process", *e, context, o));
  }
  {
    const PluginManifest m = read_plugin_manifest((scratch / "copy").string());
    auto e = plugin_estimator(m).create(resolve_params(m.name, m.params, {}, "bench"));
    process.push_back(time_estimator("cp constant.exr", "process, /bin/sh + cp", *e, context, o));
  }
  for (int frames : {1, 10}) {
    PluginManifest m = read_plugin_manifest(find_estimator("constant-copy").folder);
    m.frames = frames;
    auto e = plugin_estimator(m).create(resolve_params(m.name, m.params, {}, "bench"));
    process.push_back(time_estimator("constant-copy",
                                     "process, Python, --frames " + std::to_string(frames), *e,
                                     context, o, frames));
  }

  std::string no_device;
  if (!vk::shared_context(&no_device)) {
    glsl.push_back({"(all)", "", 0, -1, 1, "no Vulkan device (" + no_device + ")"});
  } else {
    const PluginManifest m = read_plugin_manifest((scratch / "null").string());
    auto null_e = plugin_estimator(m).create(ParamSet());
    glsl.push_back(
        time_estimator("bench-null", "GLSL plug-in, one pass storing 1", *null_e, context, o));
    auto hbao = create(find_estimator("hbao-split"), {{"gbuffer", "embree"}});
    glsl.push_back(time_estimator("hbao-split", "built-in, gbuffer=embree", *hbao, context, o));
    for (const char* name : {"alchemy", "sao"}) {
      auto e = create(find_estimator(name), {});
      glsl.push_back(time_estimator(name, "GLSL plug-in, defaults", *e, context, o));
    }
  }

  std::ostringstream md;
  md << "# aoeval bench plugins: " << o.scene << " " << w << "x" << h << ", median of "
     << o.repetitions << " runs after " << o.warmup << " warm-up\n\n## Process protocol\n\n"
     << "| estimator | what | ms per run() | own frame ms | ms per frame | overhead per frame vs "
        "constant |\n|---|---|---|---|---|---|\n";
  const double base = process.front().skipped.empty() ? process.front().wall_ms : 0.0;
  nlohmann::json jp = nlohmann::json::array(), jg = nlohmann::json::array();
  for (const Timing& t : process) {
    if (!t.skipped.empty()) {
      md << "| " << t.name << " | " << t.note << " | skipped: " << t.skipped << " |||\n";
      jp.push_back({{"name", t.name}, {"note", t.note}, {"skipped", t.skipped}});
      continue;
    }
    const double per_frame = t.wall_ms / t.frames;
    md << "| " << t.name << " | " << t.note << " | " << fixed(t.wall_ms) << " | "
       << (t.own_ms >= 0 ? fixed(t.own_ms, 4) : "-") << " | " << fixed(per_frame) << " | "
       << fixed(per_frame - base) << " |\n";
    jp.push_back({{"name", t.name},
                  {"note", t.note},
                  {"ms_per_run", t.wall_ms},
                  {"frames_per_run", t.frames},
                  {"ms_per_frame", per_frame},
                  {"overhead_ms_per_frame", per_frame - base},
                  {"own_frame_ms", t.own_ms >= 0 ? nlohmann::json(t.own_ms) : nlohmann::json()}});
  }
  md << "\n## GLSL dispatch (device: " << backend_device(Backend::vulkan) << ")\n\n"
     << "| estimator | what | wall ms per frame | GPU ms (timestamps) | overhead ms (wall - GPU) "
        "|\n|---|---|---|---|---|\n";
  for (const Timing& t : glsl) {
    if (!t.skipped.empty()) {
      md << "| " << t.name << " | " << t.note << " | skipped: " << t.skipped << " |||\n";
      jg.push_back({{"name", t.name}, {"skipped", t.skipped}});
      continue;
    }
    md << "| " << t.name << " | " << t.note << " | " << fixed(t.wall_ms) << " | " << fixed(t.own_ms)
       << " | " << fixed(t.wall_ms - t.own_ms) << " |\n";
    jg.push_back({{"name", t.name},
                  {"note", t.note},
                  {"wall_ms", t.wall_ms},
                  {"gpu_ms", t.own_ms},
                  {"overhead_ms", t.wall_ms - t.own_ms}});
  }
  std::printf("%s", md.str().c_str());
  fs::create_directories(o.out_dir);
  const nlohmann::json j = {{"scene", o.scene},   {"width", w},
                            {"height", h},        {"repetitions", o.repetitions},
                            {"warmup", o.warmup}, {"device", backend_device(Backend::vulkan)},
                            {"process", jp},      {"glsl", jg}};
  write_text((fs::path(o.out_dir) / "bench_plugins.json").string(), j.dump(2) + "\n");
  write_text((fs::path(o.out_dir) / "bench_plugins.md").string(), md.str());
}

void add_plugins_bench(CLI::App* bench) {
  static PluginBenchOptions o;
  auto* cmd = bench->add_subcommand(
      "plugins",
      "plug-in protocol overhead: process (vs constant) and GLSL dispatch (vs hbao-split)");
  cmd->add_option("--scene", o.scene, "corpus name or scene file (default bunny)");
  cmd->add_option("--view", o.view, "view name (default: the scene's first view)");
  cmd->add_option("--res", o.res, "resolution WIDTHxHEIGHT (default 640x480)");
  cmd->add_option("--warmup", o.warmup, "untimed runs first")->check(CLI::Range(0, 100));
  cmd->add_option("--repetitions", o.repetitions, "timed runs")->check(CLI::Range(1, 1000));
  cmd->add_option("--out", o.out_dir, "output folder (bench_plugins.json, bench_plugins.md)");
  cmd->callback([] { bench_plugins(o); });
}

}  // namespace aoeval
