// `aoeval bench plugins`: what the plug-in protocols cost (CONTRACT §7), on one scene view.
//
//  - process: the built-in `constant` against process plug-ins that do no work: a shell script
//    that copies a constant AO.exr (the protocol's floor: fork, exec, G-buffer and parameters
//    already written, AO.exr read back and checked) and the shipped Python `constant-copy` run
//    with --frames 1 and --frames 10 (a Python plug-in's floor, start-up included, per frame).
//    The G-buffer and P.json are written once per view in prepare(), outside the frame.
//  - glsl: a GLSL plug-in whose one pass only stores 1 against hbao-split (gbuffer=embree, the
//    same uploaded G-buffer) on the same Vulkan device: wall time of a frame (record, submit,
//    wait, download, checks) against its GPU timestamp span; the difference is the dispatch
//    overhead. alchemy and sao are timed the same way for scale.
// Writes bench_plugins.json and bench_plugins.md to --out.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include "base/resolution.h"

namespace aoeval {

struct PluginBenchOptions {
  std::string scene = "bunny";
  std::string view;
  std::string res = kDefaultBenchResolution;
  int warmup = 1;
  int repetitions = 10;
  std::string out_dir = "out/bench-plugins";
};

void bench_plugins(const PluginBenchOptions& options);
// Adds `plugins` to `aoeval bench`.
void add_plugins_bench(CLI::App* bench);

}  // namespace aoeval
