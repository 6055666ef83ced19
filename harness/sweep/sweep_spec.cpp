#include "harness/sweep/sweep_spec.h"

#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "base/errors.h"
#include "base/json_reader.h"
#include "estimators/plugins/plugin_registry.h"
#include "estimators/registry.h"
#include "scenes/corpus.h"

namespace aoeval {

EvaluationRequest evaluation_request(const SweepPoint& p) {
  EvaluationRequest req;
  req.estimator = p.estimator;
  req.overrides = p.overrides;
  req.scene = p.scene;
  req.view = p.view;
  req.width = p.width;
  req.height = p.height;
  req.seed_per_frame = p.seed_per_frame;
  return req;
}

namespace fs = std::filesystem;

namespace {

// A view entry "scene/view" whose scene is one of the spec's names that scene's view alone (two
// scenes' sequences in one sweep or tune); any other entry is a view name for every scene.
std::pair<std::string, std::string> qualified_view(const std::string& entry,
                                                   const std::vector<std::string>& scenes) {
  const size_t slash = entry.rfind('/');
  if (slash == std::string::npos ||
      std::find(scenes.begin(), scenes.end(), entry.substr(0, slash)) == scenes.end())
    return {"", entry};
  return {entry.substr(0, slash), entry.substr(slash + 1)};
}

}  // namespace

std::vector<nlohmann::json> expand_grid_values(const ParamSpec& param, const nlohmann::json& entry,
                                               const std::string& file, const std::string& path) {
  const std::string where = file + ": " + path;
  std::vector<nlohmann::json> values;
  if (entry.is_array()) {
    if (entry.empty()) throw InputError(where + ": the list of values is empty");
    for (const auto& v : entry) values.push_back(v);
    return values;
  }
  if (!entry.is_object())
    throw InputError(where + ": expected a list of values or {\"range\": ...}");
  nlohmann::json copy = entry;
  JsonReader r(copy, file, path);
  const auto& range = r.raw("range");
  // Without "scale" a range is spaced as the parameter declares (ParamSpec::log_scale).
  const std::string scale = r.choice("scale", param.log_scale ? "log" : "lin", {"lin", "log"});
  r.finish();
  if (param.type != ParamType::real && param.type != ParamType::integer)
    throw InputError(where + ": a range needs a numeric parameter");
  if (!range.is_array() || range.size() != 3 || !range[0].is_number() || !range[1].is_number() ||
      !range[2].is_number_integer())
    throw InputError(where + ".range: expected [lo, hi, steps] with an integer step count");
  const double lo = range[0].get<double>(), hi = range[1].get<double>();
  const int64_t steps = range[2].get<int64_t>();
  if (steps < 1 || steps > 100000) throw InputError(where + ".range: steps must be in [1, 100000]");
  if (scale == "log" && !(lo > 0.0 && hi > 0.0))
    throw InputError(where + ".range: a log scale needs positive bounds");
  std::set<int64_t> seen;
  for (int64_t i = 0; i < steps; ++i) {
    const double t = steps == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(steps - 1);
    const double v = scale == "log" ? lo * std::pow(hi / lo, t) : lo + (hi - lo) * t;
    if (param.type == ParamType::integer) {
      const auto iv = static_cast<int64_t>(std::llround(v));
      if (seen.insert(iv).second) values.push_back(iv);
    } else {
      values.push_back(v);
    }
  }
  return values;
}

SweepSpec parse_sweep_spec(const nlohmann::json& doc, const std::string& file) {
  JsonReader root(doc, file);
  SweepSpec spec;
  // The name becomes a folder (out/<name>) and job names: one plain path component.
  spec.name = root.string("name");
  if (spec.name.empty() || spec.name == "." || spec.name == ".." ||
      spec.name.find_first_of("/\\") != std::string::npos ||
      std::any_of(spec.name.begin(), spec.name.end(),
                  [](char c) { return static_cast<unsigned char>(c) < 0x20; }))
    root.fail("name", nlohmann::json(spec.name).dump() +
                          " is not a plain name (it names the folder out/<name>: no '/', '\\', "
                          "control characters, and not '.' or '..')");
  const auto& scenes = root.raw("scenes");
  if (!scenes.is_array() || scenes.empty())
    root.fail("scenes", "expected a non-empty list of scene names");
  for (const auto& s : scenes) {
    if (!s.is_string()) root.fail("scenes", "expected scene names");
    resolve_scene_path(s.get<std::string>());  // unknown scenes fail now, not mid-sweep
    spec.scenes.push_back(s.get<std::string>());
  }
  if (root.has("views")) {
    const auto& v = root.raw("views");
    if (v.is_string() && v.get<std::string>() == "all") {
      spec.all_views = true;
    } else if (v.is_array()) {
      if (v.empty())
        root.fail("views", "the list is empty (omit \"views\" for each scene's first view)");
      for (const auto& x : v) {
        if (!x.is_string()) root.fail("views", "expected \"all\" or a list of view names");
        spec.views.push_back(x.get<std::string>());
      }
    } else {
      root.fail("views", "expected \"all\" or a list of view names");
    }
  }
  if (root.has("res")) {
    const auto& r = root.raw("res");
    // Compared as doubles: get<int>() of 4294967328 wraps to 32 and would run silently at 32.
    auto side_ok = [](const nlohmann::json& x) {
      return x.is_number_integer() && x.get<double>() >= 1.0 && x.get<double>() <= 16384.0;
    };
    if (!r.is_array() || r.size() != 2 || !side_ok(r[0]) || !side_ok(r[1]))
      root.fail("res", "expected [width, height] with each in [1, 16384]");
    spec.width = r[0].get<int>();
    spec.height = r[1].get<int>();
  }
  if (auto ref = root.optional_object("reference")) {
    const ReferenceSpec defaults;
    spec.reference.spp = static_cast<int>(ref->integer("spp", defaults.spp, 1, 1 << 24));
    spec.reference.sampler = parse_sampler(
        ref->choice("sampler", sampler_name(defaults.sampler), {"random", "stratified", "sobol"}));
    spec.reference.seed = static_cast<uint64_t>(
        ref->integer("seed", static_cast<int64_t>(defaults.seed), 0, INT64_MAX));
    ref->finish();
  }
  if (auto t = root.optional_object("timing")) {
    const TimingSpec defaults;
    spec.timing.warmup = static_cast<int>(t->integer("warmup", defaults.warmup, 0, 1000));
    spec.timing.repetitions =
        static_cast<int>(t->integer("repetitions", defaults.repetitions, 1, 10000));
    // Adaptive (harness/evaluation/repetition_policy.h): "repetitions" is then the least.
    spec.timing.max_repetitions = static_cast<int>(
        t->integer("max_repetitions", spec.timing.repetitions, spec.timing.repetitions, 10000));
    spec.timing.median_ci = t->number("median_ci", defaults.median_ci, 0.001, 1.0);
    t->finish();
  }
  for (auto& run : root.array_of_objects("runs", 1)) {
    SweepSpec::Run r;
    const std::string name = run.string("estimator");
    try {
      r.estimator = &find_estimator(name);
      prepare_plugin_for_run(*r.estimator);  // a shader's compile error: exit 2, nothing written
    } catch (const InputError& e) {
      run.fail("estimator", e.what());
    }
    if (run.has("fixed")) {
      const auto& f = run.raw("fixed");
      if (!f.is_object()) run.fail("fixed", "expected an object of parameter values");
      r.fixed = f;
    }
    if (run.has("grid")) {
      const auto& g = run.raw("grid");
      if (!g.is_object()) run.fail("grid", "expected an object of parameter values");
      for (auto it = g.begin(); it != g.end(); ++it) {
        if (!r.estimator->find_param(it.key())) {
          // resolve_params names the known parameters
          resolve_params(name, r.estimator->params, nlohmann::json{{it.key(), 0}},
                         file + ": " + run.where("grid"));
        }
        if (r.fixed.contains(it.key())) run.fail("grid." + it.key(), "is in both grid and fixed");
      }
      // Declaration order, so run names and expansion order do not depend on the JSON's order.
      for (const auto& p : r.estimator->params) {
        if (!g.contains(p.name)) continue;
        auto values = expand_grid_values(p, g[p.name], file, run.where("grid." + p.name));
        for (const auto& v : values)  // validate every value now
          resolve_params(name, r.estimator->params, nlohmann::json{{p.name, v}},
                         file + ": " + run.where("grid"));
        r.grid.emplace_back(p.name, std::move(values));
      }
    }
    resolve_params(name, r.estimator->params, r.fixed, file + ": " + run.where("fixed"));
    r.seed_per_frame = run.boolean("seed_per_frame", true);
    run.finish();
    spec.runs.push_back(std::move(r));
  }
  root.finish();
  return spec;
}

SweepSpec load_sweep_spec(const std::string& path) {
  return parse_sweep_spec(parse_json_file(path), path);
}

std::vector<SweepPoint> expand_sweep(const SweepSpec& spec, size_t max_points) {
  // Counted in double before expanding: the product of a few large ranges overflows size_t.
  const double views_per_scene =
      spec.all_views ? 1.0 : std::max<double>(1.0, static_cast<double>(spec.views.size()));
  double planned = 0.0;
  for (const auto& run : spec.runs) {
    double product = static_cast<double>(spec.scenes.size()) * views_per_scene;
    for (const auto& [key, values] : run.grid) product *= static_cast<double>(values.size());
    planned += product;
  }
  auto too_many = [&](double count) {
    char text[64];
    std::snprintf(text, sizeof text, "%.0f", count);
    throw InputError(spec.name + ": runs: the grid expands to " + text +
                     " points, more than the limit of " + std::to_string(max_points) +
                     "; narrow the grid or raise it with --max-points");
  };
  if (planned > static_cast<double>(max_points)) too_many(planned);
  // Rows are named by the scene's file name: two files of one name would share every run name.
  std::map<std::string, std::string> path_of_name;
  for (const auto& scene : spec.scenes) {
    const std::string path = fs::weakly_canonical(resolve_scene_path(scene)).string();
    const auto [it, inserted] = path_of_name.emplace(scene_display_name(scene), path);
    if (!inserted && it->second != path)
      throw InputError(spec.name + ": scenes: " + it->second + " and " + path +
                       " are both named '" + it->first +
                       "' (rows are named by the scene's file name); rename one");
  }
  std::vector<SweepPoint> points;
  std::set<std::string> names;
  for (const auto& run : spec.runs) {
    // Cartesian product, last key fastest.
    std::vector<size_t> index(run.grid.size(), 0);
    bool done = false;
    while (!done) {
      nlohmann::json overrides = run.fixed;
      for (size_t k = 0; k < run.grid.size(); ++k)
        overrides[run.grid[k].first] = run.grid[k].second[index[k]];
      const ParamSet params =
          resolve_params(run.estimator->name, run.estimator->params, overrides, spec.name);
      for (const auto& scene : spec.scenes) {
        const std::string path = resolve_scene_path(scene);
        const std::vector<View> views = load_scene_views(path);
        std::vector<const View*> chosen;
        if (spec.all_views) {
          for (const auto& v : views)  // sequences are named: each costs frames x references
            if (!v.sequence) chosen.push_back(&v);
        } else if (spec.views.empty()) {
          chosen.push_back(&views.front());
        } else {
          for (const auto& entry : spec.views) {
            const auto [only, name] = qualified_view(entry, spec.scenes);
            if (!only.empty() && only != scene) continue;  // "scene/view": that scene's alone
            const View* found = nullptr;
            for (const auto& v : views)
              if (v.name == name) found = &v;
            if (!found)
              throw InputError(spec.name + ": views: scene " + scene + " has no view '" + name +
                               "'");
            chosen.push_back(found);
          }
          if (chosen.empty())
            throw InputError(spec.name + ": views: none applies to scene " + scene +
                             " (each names another scene)");
        }
        for (const View* v : chosen) {
          SweepPoint p;
          p.estimator = run.estimator;
          p.overrides = overrides;
          p.scene = scene;
          p.view = v->name;
          p.width = spec.width > 0 ? spec.width : v->width;
          p.height = spec.height > 0 ? spec.height : v->height;
          p.name = run_name(*run.estimator, params, overrides, scene_display_name(scene), v->name,
                            p.width, p.height);
          p.seed_per_frame = run.seed_per_frame;
          if (v->sequence && !run.seed_per_frame) p.name += "/seed_per_frame:false";
          if (names.insert(p.name).second) points.push_back(std::move(p));  // duplicates run once
          if (points.size() > max_points) too_many(static_cast<double>(points.size()));
        }
      }
      // Advance the odometer; done when every key has wrapped (at once for an empty grid).
      done = true;
      for (size_t k = run.grid.size(); k-- > 0;) {
        if (++index[k] < run.grid[k].second.size()) {
          done = false;
          break;
        }
        index[k] = 0;
      }
    }
  }
  return points;
}

std::vector<SweepPoint> select_shard(const std::vector<SweepPoint>& points, int index, int count) {
  std::vector<SweepPoint> out;
  for (size_t i = static_cast<size_t>(index); i < points.size(); i += static_cast<size_t>(count))
    out.push_back(points[i]);
  return out;
}

std::pair<int, int> parse_shard(const std::string& text) {
  if (text == "auto") {
    // A Slurm job array's task (CONTRACT §9): the same binary runs under GNU parallel or a
    // Kubernetes indexed job with an explicit I/N.
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
    if (!id || !*id || !count || !*count)
      throw InputError(
          "--shard auto: SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT are not set (not inside a "
          "Slurm job array); pass --shard I/N");
    try {
      return parse_shard(std::string(id) + "/" + count);
    } catch (const InputError&) {
      throw InputError(std::string("--shard auto: SLURM_ARRAY_TASK_ID=") + id +
                       " and SLURM_ARRAY_TASK_COUNT=" + count +
                       " do not make a shard I/N with 0 <= I < N (submit the array as --array=0-" +
                       "(N-1))");
    }
  }
  const auto slash = text.find('/');
  auto bad = [&]() -> std::pair<int, int> {
    throw InputError("--shard: expected I/N with 0 <= I < N, got '" + text + "'");
  };
  if (slash == std::string::npos) return bad();
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  if (a.empty() || b.empty() || a.find_first_not_of("0123456789") != std::string::npos ||
      b.find_first_not_of("0123456789") != std::string::npos || a.size() > 6 || b.size() > 6)
    return bad();
  const int i = std::stoi(a), n = std::stoi(b);
  if (n < 1 || i >= n) return bad();
  return {i, n};
}

}  // namespace aoeval
