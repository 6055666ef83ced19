// Timing checks that do not flip with the machine's noise. Every contender of a figure is prepared
// once, then timed in interleaved rounds (round r runs contender (r + i) mod n in position i), so
// a change of load on a shared machine hits them all alike; a check then decides with the
// dashboard's one-sided Mann-Whitney rank test (reports/regression.h) at kTimingAlpha and prints
// its p-value, instead of comparing two medians that the load can swap.
//
// Statements are of two kinds, and each is decided where the evidence can decide it:
//   "A is slower than f x B"   holds only when the test says so (p < alpha): an order is claimed;
//   "A is not faster than f x B" (a ratio within a band, no step faster by more than 5 %) fails
//                              only when the test says A is faster (p < alpha).
// Scaling one side by f before ranking tests the ratio against f (the rank test is invariant to a
// common scale, so "a > f b" is "a / f > b").
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/figures/figure.h"

namespace aoeval::figures {

inline constexpr double kTimingAlpha = 0.01;

struct Contender {
  std::string estimator;
  nlohmann::json overrides = nlohmann::json::object();
  std::string scene, view;
  int width = 0, height = 0;
};

struct InterleavedTimes {
  std::vector<std::vector<double>> ms;  // per contender, per round (the estimator's total_ms when
                                        // it reports one, else wall time around run())
  std::vector<size_t> pixels;           // per contender
  // Per contender, per pass the estimator reports in pass_ms ("horizon_ms", ...), per round.
  std::vector<std::map<std::string, std::vector<double>>> pass_ms;
  double median(size_t i) const;
};
// Prepares each contender, runs `warmup` interleaved rounds untimed, then `rounds` timed ones.
InterleavedTimes time_interleaved(FigureContext& ctx, const std::vector<Contender>& contenders,
                                  int warmup, int rounds);

// One-sided p-values of the rank test: P(a this much slower than f x b by chance) and the reverse.
double p_slower(const std::vector<double>& a, const std::vector<double>& b, double f = 1.0);
double p_faster(const std::vector<double>& a, const std::vector<double>& b, double f = 1.0);
// "p = 0.0040" for a caption (4 significant digits).
std::string p_text(double p);

}  // namespace aoeval::figures
