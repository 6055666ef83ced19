// `aoeval estimate --estimator E --scene S [--view V] [--res WxH] [--set KEY=VALUE]... -o FILE.exr`
#include <chrono>
#include <cstdio>

#include "base/errors.h"
#include "base/text_files.h"
#include "cmd/commands.h"
#include "cmd/plugin_options.h"
#include "estimators/registry.h"
#include "harness/evaluation/evaluation.h"
#include "scenes/corpus.h"

namespace aoeval {

void add_estimate_command(CLI::App& app) {
  struct Options {
    std::string estimator, scene, view, res, output;
    std::vector<std::string> sets;
  };
  static Options o;
  auto* cmd = app.add_subcommand("estimate", "one estimator, one view");
  cmd->add_option("--estimator", o.estimator, "estimator name (aoeval estimators list)")
      ->required();
  cmd->add_option("--scene", o.scene, "corpus name or scene file")->required();
  cmd->add_option("--view", o.view, "view name (default: the scene's first view)");
  cmd->add_option("--res", o.res, "resolution WIDTHxHEIGHT (default: the view's)");
  cmd->add_option("--set", o.sets, "KEY=VALUE for a parameter (aoeval estimators show E)");
  cmd->add_option("-o,--output", o.output, "output OpenEXR file")->required();
  add_plugins_option(cmd);
  cmd->callback([] {
    install_interrupt_cleanup();  // Ctrl-C leaves no temporary (text_files.h)
    remove_dead_temporaries_of(o.output);
    const EstimatorInfo& e = find_estimator(o.estimator);
    const ParamSet params = resolve_params(e.name, e.params, parse_set_arguments(o.sets), "--set");
    const auto [w, h] = parse_resolution(o.res);
    Scene scene = load_scene(o.scene);
    const View& view = scene.view(o.view);
    EmbreeScene es(scene);
    const Camera camera = make_camera(view, w, h);
    const GBuffer g = render_gbuffer(es, camera);
    const EstimateContext context{scene, es, g};
    auto estimator = e.create(params);
    EstimateResult r;
    double ms = 0.0;
    try {
      estimator->prepare(context);
      const auto t0 = std::chrono::steady_clock::now();
      r = estimator->run(context);
      ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    } catch (const EstimatorUnavailable& unavailable) {
      // No backend here (e.g. no Vulkan device): say so in the results' words, write nothing.
      std::fprintf(stderr, "aoeval: skipped: %s\n", unavailable.what());
      throw ExitStatus{1};
    }
    write_exr(o.output, estimate_to_image(g, r),
              estimate_attributes(scene, scene.content_hash(), view, camera, e, params,
                                  estimator->derived()));
    // One line: what ran where, how long its frame took (the estimator's own total when it
    // measures one, e.g. GPU timestamps; else the wall clock around run()), and the file.
    if (const auto total = r.pass_ms.find("total_ms"); total != r.pass_ms.end()) ms = total->second;
    std::printf("estimate: %s on %s/%s %dx%d: %.3f ms (one frame, after prepare) -> %s\n",
                e.name.c_str(), scene.name.c_str(), view.name.c_str(), g.width, g.height, ms,
                o.output.c_str());
  });
}

}  // namespace aoeval
