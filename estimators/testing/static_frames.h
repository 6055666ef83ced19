// Test support for estimators over time (CONTRACT §10): a registered estimator run over the frames
// of a static camera (one G-buffer, no motion) the way the temporal runner runs an estimator that
// keeps state (harness/evaluation/frames.cpp: one instance, prepare() and run() at
// every frame, frame k with seed offset k, or 0 when the run keeps one seed), and the still path
// every still view takes (no FrameInfo; run() twice, as a warm-up does).
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimators/registry.h"
#include "estimators/testing/ssao_test_scenes.h"

namespace aoeval {

inline std::vector<std::vector<float>> run_static_frames(const std::string& name,
                                                         const nlohmann::json& overrides,
                                                         const TestView& view, int frames,
                                                         bool seed_per_frame = true) {
  const EstimatorInfo& e = find_estimator(name);
  EXPECT_TRUE(e.keeps_state) << name;
  const auto est = e.create(resolve_params(e.name, e.params, overrides, "test"));
  std::vector<std::vector<float>> out;
  for (int k = 0; k < frames; ++k) {
    const FrameInfo info{.index = k,
                         .count = frames,
                         .fps = 30.0,
                         .seed_offset = seed_per_frame ? static_cast<uint64_t>(k) : 0};
    const EstimateContext c{view.scene, *view.embree, view.gbuffer, &info};
    est->prepare(c);
    out.push_back(est->run(c).ao);
  }
  return out;
}

inline EstimateResult run_still_frame(const std::string& name, const nlohmann::json& overrides,
                                      const TestView& view, nlohmann::json* derived = nullptr) {
  const EstimatorInfo& e = find_estimator(name);
  const auto est = e.create(resolve_params(e.name, e.params, overrides, "test"));
  const EstimateContext c{view.scene, *view.embree, view.gbuffer};
  est->prepare(c);
  est->run(c);  // a warm-up: run() is repeatable
  EstimateResult r = est->run(c);
  if (derived) *derived = est->derived();
  return r;
}

// The settings a registered estimator's parameters give (`settings_of`: gtao_settings_of,
// hbao_settings_of) with `overrides`, at sequence frame `frame` (Settings::frame).
template <class SettingsOf>
auto settings_at_frame(const std::string& name, SettingsOf settings_of,
                       const nlohmann::json& overrides, uint64_t frame) {
  const EstimatorInfo& info = find_estimator(name);
  auto s = settings_of(resolve_params(info.name, info.params, overrides, "test"));
  s.frame = frame;
  return s;
}

}  // namespace aoeval
