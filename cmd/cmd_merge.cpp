// `aoeval merge DIR... --out DIR [--db FILE] [--plan FILE]` (CONTRACT §9): shard folders into one
// result set (cluster/merge.h), then, for suite runs, the same pages `aoeval run` writes.
#include <cstdio>
#include <filesystem>

#include "cmd/commands.h"
#include "harness/cluster/merge.h"
#include "reports/run_pages.h"

namespace aoeval {

void add_merge_command(CLI::App& app) {
  static MergeOptions o;
  auto* cmd = app.add_subcommand(
      "merge", "merge the output folders of shards or machines into one result set and report");
  cmd->add_option("DIR", o.dirs, "output folders of shards (sweep --shard, run --shard, --slurm)")
      ->required();
  cmd->add_option("--out", o.out, "the merged folder")->required();
  cmd->add_option("--db", o.database, "SQLite results store the merged rows are appended to");
  cmd->add_option("--plan", o.plan,
                  "a --slurm submission's shard plan: every planned point must be present");
  cmd->callback([] {
    o.pages = write_run_pages;
    const MergeResult m = merge_results(o);
    const std::string page =
        m.page.empty() ? (std::filesystem::path(m.out) / "results.csv").string() : m.page;
    std::fprintf(stderr, "merge: %zu rows from %zu folders (%zu duplicates kept once) -> %s\n",
                 m.rows.size(), o.dirs.size(), m.duplicates, m.out.c_str());
    for (const ShardTiming& t : m.timings)
      std::fprintf(stderr, "merge: shard %d on %s: %.2f s measured, %.3f s planned\n", t.index,
                   t.node.c_str(), t.wall_s, t.planned_ms / 1000.0);
    if (m.measured_ratio > 0.0 || m.planned_ratio > 0.0)
      std::fprintf(stderr, "merge: slowest/mean shard: %.3f measured, %.3f planned\n",
                   m.measured_ratio, m.planned_ratio);
    std::printf("%s\n", page.c_str());
  });
}

}  // namespace aoeval
