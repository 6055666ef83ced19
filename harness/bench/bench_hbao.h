// `aoeval bench hbao`: how close hbao-split comes to the device's fetch limit, and how it compares
// with its CPU twin on the same G-buffer.
//
//  - fetch efficiency: hbao-split's depth fetches per second (the fetches of its horizon and
//    normal passes, counted exactly by the CPU twin, which makes the same ones, over the GPU time
//    of those passes) against a bare shader that makes as many nearest-texel fetches per pixel
//    along screen-space walks of the same step length and does nothing else, timed in the same
//    run on the same device. Target: ratio >= 0.5.
//  - twin: hbao-split against hbao-split-cpu (TBB over rows, -O3 vectorised) on the same
//    G-buffer: median times per pass and the speed-up, and their max |difference|.
// Writes bench_hbao.json and bench_hbao.md to --out, and results rows (results.csv/json, SQLite).
#pragma once

#include "harness/bench/twin_bench.h"

namespace aoeval {

using HbaoBenchOptions = TwinBenchOptions;  // out_dir default: out/bench-hbao

void bench_hbao(const HbaoBenchOptions& options);

}  // namespace aoeval
