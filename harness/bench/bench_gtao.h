// `aoeval bench gtao`: gtao on the Vulkan device against its CPU twin (gtao-cpu) on the same
// G-buffer: median times per pass (geometry with gbuffer=raster, horizon = horizons and integrals,
// denoise), the speed-up, horizon samples per second (slices x 2 sides x steps per covered pixel,
// four depth fetches each: the bilinear 1/z), and how the twins agree (max |difference| of AO and
// bent normals, and the number of pixels that are not bit-identical).
// Writes bench_gtao.json and bench_gtao.md to --out, and results rows (results.csv/json, SQLite).
#pragma once

#include "harness/bench/twin_bench.h"

namespace aoeval {

using GtaoBenchOptions = TwinBenchOptions;  // out_dir default: out/bench-gtao

void bench_gtao(const GtaoBenchOptions& options);

}  // namespace aoeval
