// What the plug-in tests share: writing a plug-in folder, and a small rendered view to run it on.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "base/testing/test_temp_dir.h"
#include "estimators/plugins/plugin_registry.h"
#include "estimators/testing/ssao_test_scenes.h"

namespace aoeval::plugin_test {

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// A plug-in folder `dir` with estimator.json = `manifest` (a JSON object's text) and extra files.
inline std::string make_plugin(const std::filesystem::path& dir, const std::string& manifest,
                               const std::vector<std::pair<std::string, std::string>>& files = {}) {
  write_file(dir / "estimator.json", manifest);
  for (const auto& [name, text] : files) write_file(dir / name, text);
  return dir.string();
}

// Runs a plug-in estimator once (prepare + run) on `view` with default parameters.
inline EstimateResult run_plugin(const std::string& folder, const TestView& view,
                                 const nlohmann::json& overrides = nlohmann::json::object()) {
  const EstimatorInfo info = plugin_estimator(read_plugin_manifest(folder));
  const ParamSet params = resolve_params(info.name, info.params, overrides, "test");
  auto estimator = info.create(params);
  const EstimateContext context{view.scene, *view.embree, view.gbuffer};
  estimator->prepare(context);
  return estimator->run(context);
}

}  // namespace aoeval::plugin_test
