// The estimator module interface. Each estimator lives in its own folder and declares, once: its
// parameters (name, type, default, range, unit, meaning), the AO definition it estimates (possibly
// from its parameters, e.g. dmax = R), its backend and its inputs. The command line (--set),
// sweeps, JSON, EXR headers, results columns and reports all read that one declaration.
// Estimators know scenes and G-buffers, never the harness.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "base/param_text.h"
#include "scenes/ao_definition.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"
#include "scenes/scene.h"

namespace aoeval {

enum class ParamType { real, integer, boolean, choice };
const char* param_type_name(ParamType t);

// One parameter, declared once (XeGTAO's settings, pbrt's parameter dictionaries). Rows are written
// with the builders below, one per type, each field by name (RealParam, ...).
struct ParamSpec {
  std::string name;  // the --set key and the results column
  ParamType type = ParamType::real;
  nlohmann::json default_value;      // number, bool or string
  double min = 0.0, max = 0.0;       // inclusive range (real and integer)
  bool log_scale = false;            // how sweeps and plots should space it
  std::string unit;                  // "scene units", "rays", "directions", "" ...
  std::string meaning;               // one line, citing the paper's equation or section
  std::vector<std::string> choices;  // for ParamType::choice
};

// How sweeps and plots space a number parameter's values (ParamSpec::log_scale).
enum class Spacing { linear, log };

// The ParamSpec rows of each type, written as names, not positions (STYLE: C++20 designated
// initialisers, every field named, so a row reads like XeGTAO's commented settings):
//   real_param({.name = "R", .def = 0.3, .min = 1e-4, .max = 1e4, .spacing = Spacing::log,
//               .unit = "scene units", .meaning = "..."})
// A number has a default, an inclusive range, a spacing and a unit ("" for none); a boolean or a
// choice has none of these (ParamSpec's 0, 0, linear, ""), and only a choice has choices.
struct RealParam {
  std::string name;
  double def;
  double min, max;
  Spacing spacing;
  std::string unit, meaning;
};
struct IntParam {
  std::string name;
  int64_t def;
  double min, max;
  Spacing spacing;
  std::string unit, meaning;
};
struct BoolParam {
  std::string name;
  bool def;
  std::string meaning;
};
struct ChoiceParam {
  std::string name;
  std::string def;
  std::vector<std::string> choices;
  std::string meaning;
};
ParamSpec real_param(RealParam p);
ParamSpec int_param(IntParam p);
ParamSpec bool_param(BoolParam p);
ParamSpec choice_param(ChoiceParam p);

// A complete, validated set of parameter values: every declared parameter, defaults filled in.
class ParamSet {
 public:
  ParamSet() = default;
  explicit ParamSet(nlohmann::json values) : values_(std::move(values)) {}
  double real(const std::string& name) const;
  int64_t integer(const std::string& name) const;
  bool boolean(const std::string& name) const;
  std::string choice(const std::string& name) const;
  const nlohmann::json& json() const { return values_; }

  // The names read so far through real/integer/boolean/choice, by this set and every copy of it (a
  // shared log): which declared parameters an estimator actually used. The default-agreement test
  // (harness/evaluation/defaults_agreement_test.cpp) proves with it that each one is read from the
  // table rather than fixed in code.
  std::set<std::string> read_names() const;

 private:
  void note_read(const std::string& name) const;
  nlohmann::json values_ = nlohmann::json::object();
  struct ReadLog {
    std::mutex mutex;
    std::set<std::string> names;
  };
  std::shared_ptr<ReadLog> reads_ = std::make_shared<ReadLog>();
};

// Builds the ParamSet from overrides. `overrides` holds JSON values (numbers, bools, strings; a
// string for a number parameter is parsed, as --set values arrive as text). Unknown keys, wrong
// types and out-of-range values are InputErrors naming `where`, the key and the allowed range.
ParamSet resolve_params(const std::string& estimator, const std::vector<ParamSpec>& specs,
                        const nlohmann::json& overrides, const std::string& where);
// "KEY=VALUE" strings from --set into an overrides object (values kept as text).
nlohmann::json parse_set_arguments(const std::vector<std::string>& assignments);
// format_param_value (param_text.h): the stable name fragment of a parameter value.

enum class Backend { cpu, embree, vulkan, process };  // process: a plug-in program (CONTRACT §7)
const char* backend_name(Backend b);

// Thrown from Estimator::prepare()/run() when the estimator's backend is missing on this machine
// (e.g. no Vulkan device). what() is the skip reason, "no Vulkan device (<why>)": the harness
// records the row as "skipped: <what()>" with empty metrics and carries on with the others, and
// `aoeval estimate` prints that line and exits 1. Not for bad input (InputError) or bugs.
class EstimatorUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class EstimatorInput { gbuffer, scene_geometry, tree_proxies };
const char* input_name(EstimatorInput i);

// Where a frame sits in a sequence (CONTRACT §10). The G-buffer of a sequence frame carries motion
// and disoccluded; `scene` and `embree` are the frame's posed geometry.
struct FrameInfo {
  int index = 0;  // k
  int count = 1;  // frames in the sequence
  double fps = 30.0;
  uint64_t seed_offset = 0;  // k under the seed rule, 0 when the run says "seed_per_frame": false
};

// What an estimator sees when it runs.
struct EstimateContext {
  const Scene& scene;
  const EmbreeScene& embree;
  const GBuffer& gbuffer;
  const FrameInfo* frame = nullptr;  // null for a still view
};

struct EstimateResult {
  std::vector<float> ao;  // per pixel, in [0, 1]; ignored where the G-buffer has A = 0
  std::map<std::string, std::vector<float>> extra_channels;  // documented by the estimator
  // Per-pass times in ms (e.g. "horizon_ms") for backends that time themselves (GPU timestamps);
  // when "total_ms" is present the harness uses it as the estimator's time instead of wall time.
  std::map<std::string, double> pass_ms;
  // Where the frame time comes from, the results' timing_source: "" = the harness's wall clock
  // around run(), or GPU timestamps when pass_ms has "total_ms"; plug-ins name theirs
  // ("plugin-frames", "process-wall", "frame-wall").
  std::string timing_source;
};

class Estimator {
 public:
  virtual ~Estimator() = default;
  // Work done once per scene and view before frames (baking, BVH, uploads): timed separately as
  // precompute_ms.
  virtual void prepare(const EstimateContext& context) {}
  // One frame. Must be repeatable: the harness calls it warmup + repetitions times.
  virtual EstimateResult run(const EstimateContext& context) = 0;
  // What prepare() derived from the scene instead of taking it from a parameter (tree proxies,
  // alpha*rho, ...): the harness writes it into the results' params and the EXR's aoeval:params
  // under "derived", so every row says exactly what was used.
  virtual nlohmann::json derived() const { return nlohmann::json::object(); }
};

// What the conformance test (harness/evaluation/conformance_test.cpp) may expect of an estimator
// on analytic scenes. Every field has a default that follows from the backend, so a new estimator
// is checked without declaring anything; declare a field only to say why it differs.
struct ConformanceSpec {
  // Largest |AO - 1| on an open plane. < 0: by backend: 1e-6 for embree (ray casting into the
  // scene: every ray above a lone plane escapes), 0.05 for the others (screen-space and model
  // approximations, which may darken an open plane a little through their bias terms).
  double open_plane_tolerance = -1.0;
  // Whether it sees every occluder around a point, so that inside a closed box its AO is at most
  // its definition's ray value at the box's diagonal. -1: by backend (embree yes, others no: a
  // depth buffer does not hold the walls behind the camera); 0 no; 1 yes.
  int sees_enclosure = -1;
};

struct EstimatorInfo {
  std::string name;     // "raytraced", "hbao-split", ...
  std::string summary;  // one line
  std::string paper;    // authors, year, title, and the equations implemented
  Backend backend = Backend::cpu;
  std::vector<EstimatorInput> inputs;
  std::vector<ParamSpec> params;
  std::string definition_doc;  // how the AO definition follows from the parameters
  std::function<AoDefinition(const ParamSet&)> definition;
  std::function<std::unique_ptr<Estimator>(const ParamSet&)> create;
  std::string kind = "built-in";  // or a plug-in's kind: "process", "glsl" (CONTRACT §7)
  std::string folder;             // a plug-in's folder; "" for built-ins
  ConformanceSpec conformance;    // defaults by backend; see ConformanceSpec
  // Over a sequence (CONTRACT §10): false (every built-in today) = no temporal design of its own:
  // each frame runs on a fresh instance created with seed + k (the seed rule), prepared with that
  // frame's scene. true = one instance runs every frame in order and keeps its state; prepare() is
  // called at every frame with that frame's scene, and the instance applies the seed rule itself
  // from EstimateContext::frame->seed_offset.
  bool keeps_state = false;
  // Its first run after prepare() was measured to cost what the later ones do, so the timing's
  // warm-up (CONTRACT §5 "warmup") is not run for it whatever its backend (warms_up()). Declare it
  // only with that measurement (shadowmap-ao's, README "The cold run's critical path").
  bool first_run_is_warm = false;

  const ParamSpec* find_param(const std::string& name) const;
  // Whether the timing's warm-up runs before its timed runs: for a Vulkan estimator (the driver's
  // pipeline and shader JIT, the first touch of its buffers on the first dispatch) and a plug-in
  // process, unless first_run_is_warm; a CPU or Embree estimator is timed cold (issue 42).
  bool warms_up() const;
  // ConformanceSpec with the backend's defaults filled in.
  double open_plane_tolerance() const;
  bool sees_enclosure() const;
};

// Every declared parameter at its declared default: what the estimator runs with when nothing is
// set. Settings structs hold no defaults of their own; tests and benches start from this.
ParamSet default_params(const EstimatorInfo& info);

}  // namespace aoeval
