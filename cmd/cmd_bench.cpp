// `aoeval bench ...`: timing tables and throughput figures. Benchmarks measure; tests never time.
#include "cmd/bench_plugins.h"
#include "cmd/commands.h"
#include "cmd/plugin_options.h"
#include "harness/bench/bench_estimators.h"
#include "harness/bench/bench_gtao.h"
#include "harness/bench/bench_hbao.h"
#include "harness/bench/bench_reference.h"
#include "harness/bench/bench_rtao.h"
#include "harness/bench/bench_scale.h"
#include "harness/bench/bench_shadowmap.h"

namespace aoeval {

namespace {

// The options of a twin bench (`bench hbao`, `bench gtao`): `estimator` names the GPU one, `stem`
// the files it writes, `out_dir` their default folder.
void add_twin_bench_options(CLI::App& cmd, TwinBenchOptions& o, const std::string& estimator,
                            const std::string& stem, const std::string& out_dir) {
  o.out_dir = out_dir;
  // Defaults are shown from the options' own values (capture_default_str), not written again here.
  cmd.add_option("--scene", o.scene, "corpus name or scene file")->capture_default_str();
  cmd.add_option("--view", o.view, "view name (default: the scene's first view)");
  cmd.add_option("--res", o.res, "resolution WIDTHxHEIGHT")->capture_default_str();
  cmd.add_option("--set", o.sets, "KEY=VALUE for " + estimator + " (repeatable)");
  cmd.add_option("--warmup", o.warmup, "untimed runs first")->check(CLI::Range(0, 100));
  cmd.add_option("--repetitions", o.repetitions, "timed runs")->check(CLI::Range(1, 1000));
  cmd.add_option("--out", o.out_dir,
                 "output folder (" + stem + ".json, " + stem + ".md, results.*)");
  cmd.add_option("--db", o.database, "SQLite results store");
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "timing tables and throughput figures");
  cmd->require_subcommand(1);
  add_bench_harness_command(*cmd);
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

  static ScaleBenchOptions scale;
  auto* sc = cmd->add_subcommand(
      "scale", "cost against the number of instanced trees: build, memory, Mrays/s, estimators");
  sc->add_option("--scene", scale.base, "corpus scene whose placers are rescaled");
  sc->add_option("--counts", scale.counts, "numbers of trees")->check(CLI::Range(1, 10000000));
  sc->add_option("--res", scale.res, "resolution WIDTHxHEIGHT");
  sc->add_option("--spp", scale.spp, "reference rays per pixel")->check(CLI::Range(1, 65536));
  sc->add_option("--repetitions", scale.repetitions, "timed runs")->check(CLI::Range(1, 1000));
  sc->add_option("--copies-max", scale.copies_max, "build copies for N up to this");
  sc->add_option("--cull", scale.cull, "cull_occlusion of the tree estimators")
      ->check(CLI::Range(0.0, 0.25));
  sc->add_flag("--cached-references", scale.cached_references,
               "serve references from the reference cache and fill it (no Mrays/s then)");
  sc->add_option("--far", scale.far, "far_field_angle of the far-field rows (repeatable)")
      ->check(CLI::Range(0.0, 0.9));
  sc->add_option("--out", scale.out_dir, "output folder (bench_scale.json, .md, .png)");
  sc->callback([] { bench_scale(scale); });

  static EstimatorBenchOptions est;
  auto* estimators =
      cmd->add_subcommand("estimators", "timing table: median/min/max ms and Mpixel/s");
  estimators->add_option("--scene", est.scenes, "scenes (repeatable)");
  estimators->add_option("--estimator", est.estimators, "estimators (repeatable; default all)");
  estimators->add_option("--set", est.sets, "KEY=VALUE for estimators that have the key");
  estimators->add_option("--res", est.res, "resolution WIDTHxHEIGHT");
  estimators->add_option("--warmup", est.warmup, "untimed runs first")->check(CLI::Range(0, 1000));
  estimators->add_option("--repetitions", est.repetitions, "timed runs")
      ->check(CLI::Range(1, 10000));
  estimators->add_option("--out", est.out_dir, "output folder (bench.csv, bench.md, results.*)");
  estimators->add_option("--db", est.database, "SQLite results store");
  add_plugins_option(estimators);
  estimators->callback([] { bench_estimators(est); });

  static TwinBenchOptions hb;
  auto* hbao = cmd->add_subcommand(
      "hbao",
      "hbao-split: depth fetches/s against a bare fetch loop (target ratio >= 0.5), and "
      "against hbao-split-cpu on the same G-buffer");
  add_twin_bench_options(*hbao, hb, "hbao-split", "bench_hbao", "out/bench-hbao");
  hbao->callback([] { bench_hbao(hb); });

  static TwinBenchOptions gt;
  auto* gtao = cmd->add_subcommand(
      "gtao",
      "gtao: GPU time per pass, horizon samples/s, and against gtao-cpu on the same G-buffer");
  add_twin_bench_options(*gtao, gt, "gtao", "bench_gtao", "out/bench-gtao");
  gtao->callback([] { bench_gtao(gt); });

  static ShadowmapBenchOptions sm;
  auto* shadowmap = cmd->add_subcommand(
      "shadowmap", "shadowmap-ao: time per pass against the number of lights and the map size");
  shadowmap->add_option("--scene", sm.scene, "corpus name or scene file")->capture_default_str();
  shadowmap->add_option("--res", sm.res, "camera resolution WIDTHxHEIGHT")->capture_default_str();
  shadowmap->add_option("--lights", sm.lights, "light counts (repeatable)")
      ->check(CLI::Range(1, 4096));
  shadowmap->add_option("--map-res", sm.resolutions, "shadow-map resolutions (repeatable)")
      ->check(CLI::Range(16, 4096));
  shadowmap->add_option("--set", sm.sets, "further KEY=VALUE for shadowmap-ao (repeatable)");
  shadowmap->add_option("--warmup", sm.warmup, "untimed runs first")->check(CLI::Range(0, 100));
  shadowmap->add_option("--repetitions", sm.repetitions, "timed runs")->check(CLI::Range(1, 1000));
  shadowmap->add_option("--out", sm.out_dir, "output folder (bench_shadowmap.md/csv, results.*)");
  shadowmap->add_option("--db", sm.database, "SQLite results store");
  shadowmap->callback([] { bench_shadowmap(sm); });

  static RtaoBenchOptions rt;
  auto* rtao = cmd->add_subcommand(
      "rtao",
      "rtao: ms per frame and per pass (rays, temporal, variance, each a-trous pass) on a "
      "static-camera sequence");
  rtao->add_option("--scene", rt.scene, "corpus name or scene file (default bunny)");
  rtao->add_option("--view", rt.view, "view name (default: the scene's first view)");
  rtao->add_option("--res", rt.res, "resolution WIDTHxHEIGHT (default 640x480)");
  rtao->add_option("--frames", rt.frames, "frames of the sequence (default 16)")
      ->check(CLI::Range(2, 4096));
  rtao->add_option("--set", rt.sets, "KEY=VALUE for rtao (repeatable)");
  rtao->add_option("--warmup", rt.warmup, "untimed sequences first")->check(CLI::Range(0, 100));
  rtao->add_option("--repetitions", rt.repetitions, "timed sequences (default 3)")
      ->check(CLI::Range(1, 100));
  rtao->add_option("--out", rt.out_dir, "output folder (bench_rtao.md/csv, results.*)");
  rtao->add_option("--db", rt.database, "SQLite results store");
  rtao->callback([] { bench_rtao(rt); });

  // The same sequence bench for any estimator that keeps state (gtao with temporal=true).
  static RtaoBenchOptions tp = [] {
    RtaoBenchOptions o;
    o.estimator = "gtao";
    o.out_dir = "out/bench-temporal";
    return o;
  }();
  auto* temporal = cmd->add_subcommand(
      "temporal",
      "an estimator that keeps state over a sequence (default gtao; set temporal=true for its "
      "temporal stage): ms per frame and per pass on a static-camera sequence");
  temporal->add_option("--estimator", tp.estimator, "estimator name (default gtao)");
  temporal->add_option("--scene", tp.scene, "corpus name or scene file (default bunny)");
  temporal->add_option("--view", tp.view, "view name (default: the scene's first view)");
  temporal->add_option("--res", tp.res, "resolution WIDTHxHEIGHT (default 640x480)");
  temporal->add_option("--frames", tp.frames, "frames of the sequence (default 16)")
      ->check(CLI::Range(2, 4096));
  temporal->add_option("--set", tp.sets, "KEY=VALUE for the estimator (repeatable)");
  temporal->add_option("--warmup", tp.warmup, "untimed sequences first")->check(CLI::Range(0, 100));
  temporal->add_option("--repetitions", tp.repetitions, "timed sequences (default 3)")
      ->check(CLI::Range(1, 100));
  temporal->add_option("--out", tp.out_dir, "output folder (bench_<estimator>.md/csv, results.*)");
  temporal->add_option("--db", tp.database, "SQLite results store");
  temporal->callback([] { bench_rtao(tp); });
  add_plugins_bench(cmd);
}

}  // namespace aoeval
