// The subcommands of `aoeval` (CONTRACT §2). Each add_* function registers one subcommand with its
// options and the callback that runs it; main.cpp only assembles them and maps errors to exit
// codes.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>

namespace aoeval {

void add_scenes_command(CLI::App& app);
void add_gbuffer_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_reference_command(CLI::App& app);
void add_estimators_command(CLI::App& app);
void add_estimate_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_sweep_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_figures_command(CLI::App& app);
void add_dashboard_command(CLI::App& app);
void add_merge_command(CLI::App& app);

// "640x480" -> {640, 480}; {0, 0} for "". InputError naming `option` otherwise.
std::pair<int, int> parse_resolution(const std::string& text, const std::string& option = "--res");

}  // namespace aoeval
