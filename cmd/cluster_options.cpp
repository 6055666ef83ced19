#include "cmd/cluster_options.h"

#include <filesystem>

#include "base/errors.h"

namespace aoeval {

void add_cluster_options(CLI::App* cmd, ClusterOptions& c) {
  cmd->add_flag("--slurm", c.slurm,
                "submit to Slurm with sbatch: a reference stage, an array of cost-balanced "
                "shards and a merge job (CONTRACT §9); prints the job ids and the report's path");
  cmd->add_option("--slurm-arg", c.slurm_args,
                  "an option for every sbatch, e.g. --slurm-arg=--partition=gpu (repeatable)");
  cmd->add_option("--shards", c.shards, "with --slurm: the number of estimator shards")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--sbatch-timeout", c.sbatch_timeout_s,
                  "with --slurm: seconds to wait for each sbatch before giving up (exit 2)")
      ->check(CLI::Range(1.0, 3600.0));
  cmd->add_flag("--references-only", c.references_only,
                "compute the distinct references of this shard (--shard) into the cache and "
                "stop: the reference stage of --slurm");
}

void check_cluster_options(const CLI::App* cmd, const ClusterOptions& c) {
  if (!c.slurm) return;
  for (const char* option : {"--shard", "--shard-plan", "--references-only"})
    if (cmd->count(option) > 0)
      throw InputError(std::string(option) +
                       ": cannot be combined with --slurm (--slurm plans and submits its own "
                       "shards; choose their number with --shards N)");
}

void add_plugin_args(const CLI::App* cmd, std::vector<std::string>& args) {
  const CLI::Option* plugins = cmd->get_option_no_throw("--plugins");
  if (!plugins) return;
  for (const std::string& dir : plugins->results()) {
    args.push_back("--plugins");
    args.push_back(std::filesystem::absolute(dir).string());
  }
}

}  // namespace aoeval
