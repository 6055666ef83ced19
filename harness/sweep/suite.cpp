#include "harness/sweep/suite.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "base/errors.h"
#include "base/json_reader.h"
#include "estimators/registry.h"
#include "harness/evaluation/repetition_policy.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

std::string suites_dir() {
  return std::string(AOEVAL_SOURCE_DIR) + "/harness/suites";
}

}  // namespace

std::vector<std::string> shipped_suites() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(suites_dir(), ec))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string suite_file(const std::string& name_or_path) {
  const bool is_path =
      name_or_path.find('/') != std::string::npos || fs::path(name_or_path).extension() == ".json";
  if (is_path) {
    if (!fs::is_regular_file(name_or_path))
      throw InputError("--suite: " + name_or_path + ": no such file");
    return name_or_path;
  }
  const fs::path file = fs::path(suites_dir()) / (name_or_path + ".json");
  if (!fs::is_regular_file(file)) {
    std::string known;
    for (const auto& n : shipped_suites()) {
      if (!known.empty()) known.append(", ");
      known.append(n);
    }
    throw InputError("--suite: unknown suite '" + name_or_path + "' (shipped: " + known +
                     "; or give a path to a suite file ending in .json)");
  }
  return file.string();
}

Suite parse_suite(const nlohmann::json& doc, const std::string& file, const std::string& name) {
  Suite suite;
  suite.name = name;
  suite.path = file;
  if (doc.is_object()) {
    suite.specs.push_back(parse_sweep_spec(doc, file));
  } else if (doc.is_array() && !doc.empty()) {
    for (size_t i = 0; i < doc.size(); ++i)
      suite.specs.push_back(parse_sweep_spec(doc[i], file + "[" + std::to_string(i) + "]"));
  } else {
    throw InputError(file + ": expected a sweep specification or a non-empty list of them");
  }
  return suite;
}

Suite load_suite(const std::string& name_or_path) {
  const std::string file = suite_file(name_or_path);
  return parse_suite(parse_json_file(file), file, fs::path(file).stem().string());
}

SuiteOverride parse_suite_override(const std::string& text) {
  const auto colon = text.find(':');
  const auto equals = text.find('=');
  if (colon == std::string::npos || equals == std::string::npos || colon == 0 || equals < colon + 2)
    throw InputError("--set: expected ESTIMATOR:KEY=VALUE, got '" + text + "'");
  return {text.substr(0, colon), text.substr(colon + 1, equals - colon - 1),
          text.substr(equals + 1)};
}

void apply_suite_overrides(Suite& suite, const std::vector<SuiteOverride>& overrides) {
  for (const auto& o : overrides) {
    const std::string where = "--set " + o.estimator + ":" + o.key + "=" + o.value;
    const EstimatorInfo* info = nullptr;
    try {
      info = &find_estimator(o.estimator);
    } catch (const InputError& e) {
      throw InputError(where + ": " + e.what());
    }
    // resolve_params names unknown keys with the known ones, and out-of-range values with the
    // range; the resolved value is typed (a --set value arrives as text).
    const ParamSet resolved =
        resolve_params(info->name, info->params, nlohmann::json{{o.key, o.value}}, where);
    const nlohmann::json value = resolved.json()[o.key];
    size_t runs = 0;
    for (auto& spec : suite.specs) {
      for (auto& run : spec.runs) {
        if (run.estimator != info) continue;
        ++runs;
        run.grid.erase(std::remove_if(run.grid.begin(), run.grid.end(),
                                      [&](const auto& g) { return g.first == o.key; }),
                       run.grid.end());
        run.fixed[o.key] = value;
      }
    }
    if (runs == 0)
      throw InputError(where + ": suite " + suite.name + " does not run estimator " + o.estimator);
  }
}

std::vector<SuitePoint> expand_suite(const Suite& suite) {
  std::vector<SuitePoint> points;
  std::map<std::string, size_t> seen;  // key -> index in points
  for (size_t s = 0; s < suite.specs.size(); ++s) {
    const SweepSpec& spec = suite.specs[s];
    // Which runs are gridless: expand each run on its own so points keep their run's kind.
    for (const auto& run : spec.runs) {
      SweepSpec one = spec;
      one.runs = {run};
      for (auto& p : expand_sweep(one)) {
        const ParamSet params =
            resolve_params(p.estimator->name, p.estimator->params, p.overrides, spec.name);
        const std::string key = p.estimator->name + "|" + params.json().dump() + "|" + p.scene +
                                "|" + p.view + "|" + std::to_string(p.width) + "x" +
                                std::to_string(p.height) + "|" + spec.reference.to_json().dump() +
                                "|" + timing_key(spec.timing);
        const auto [it, fresh] = seen.emplace(key, points.size());
        if (!fresh) {  // already listed: it keeps its place and becomes featured if this one is
          points[it->second].featured = points[it->second].featured || run.grid.empty();
          continue;
        }
        points.push_back({std::move(p), s, run.grid.empty()});
      }
    }
  }
  // Every (estimator, scene, view) gets a featured point.
  std::set<std::string> featured;
  auto pairing = [](const SweepPoint& p) {
    return p.estimator->name + "|" + p.scene + "|" + p.view;
  };
  for (const auto& p : points)
    if (p.featured) featured.insert(pairing(p.point));
  for (auto& p : points)
    if (featured.insert(pairing(p.point)).second) p.featured = true;
  return points;
}

}  // namespace aoeval
