// `aoeval bench gtao`: gtao on the Vulkan device against its CPU twin (gtao-cpu) on the same
// G-buffer: median times per pass (geometry with gbuffer=raster, horizon = horizons and integrals,
// denoise), the speed-up, horizon samples per second (slices x 2 sides x steps per covered pixel,
// four depth fetches each: the bilinear 1/z), and how the twins agree (max |difference| of AO and
// bent normals, and the number of pixels that are not bit-identical).
// Writes bench_gtao.json and bench_gtao.md to --out, and results rows (results.csv/json, SQLite).
#pragma once

#include <string>
#include <vector>

namespace aoeval {

struct GtaoBenchOptions {
  std::string scene = "bunny";
  std::string view;
  std::string res = "640x480";
  std::vector<std::string> sets;  // KEY=VALUE for gtao (gbuffer applies to the GPU only)
  int warmup = 1;
  int repetitions = 5;
  std::string out_dir = "out/bench-gtao";
  std::string database = "out/results.sqlite";
};

void bench_gtao(const GtaoBenchOptions& options);

}  // namespace aoeval
