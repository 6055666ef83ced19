// The options `sweep` and `run` share for runs past one machine (CONTRACT §9): --slurm,
// --slurm-arg, --shards, and the reference stage's --references-only (used by the jobs --slurm
// writes).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "harness/cluster/slurm_submit.h"

namespace aoeval {

void add_cluster_options(CLI::App* command, ClusterOptions& options);
// InputError (exit 2) for --shard, --shard-plan or --references-only given with --slurm: a
// submission is the whole run, its shards are the jobs'.
void check_cluster_options(const CLI::App* command, const ClusterOptions& options);
// Appends "--plugins DIR" for each --plugins the command was given, so every job sees the same
// estimators.
void add_plugin_args(const CLI::App* command, std::vector<std::string>& args);

}  // namespace aoeval
