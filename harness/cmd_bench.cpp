// `aoeval bench ...`: timing tables and throughput figures. Benchmarks measure; tests never time.
#include "bench_reference.h"
#include "commands.h"

namespace aoeval {

void add_bench_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "timing tables and throughput figures");
  cmd->require_subcommand(1);
  static ReferenceBenchOptions ref;
  auto* reference = cmd->add_subcommand(
      "reference", "reference rays/s against a bare Embree loop; sampler RMSE at equal rays");
  reference->add_option("--scene", ref.scene, "corpus name or scene file")->required();
  reference->add_option("--view", ref.view, "view name (default: the scene's first view)");
  reference->add_option("--res", ref.res, "resolution WIDTHxHEIGHT (default: the view's)");
  reference->add_option("--spp", ref.spp, "rays per pixel")->check(CLI::Range(1, 65536));
  reference->add_option("--repetitions", ref.repetitions, "timed repetitions")
      ->check(CLI::Range(1, 100));
  reference->add_option("--accuracy-res", ref.accuracy_res, "resolution of the accuracy part");
  reference->add_option("--truth-spp", ref.truth_spp, "rays per pixel of the accuracy truth")
      ->check(CLI::Range(1, 1 << 24));
  reference->add_flag("--skip-accuracy", ref.skip_accuracy, "throughput only");
  reference->callback([] { bench_reference(ref); });
}

}  // namespace aoeval
