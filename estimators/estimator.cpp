#include "estimators/estimator.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "base/errors.h"

namespace aoeval {

const char* param_type_name(ParamType t) {
  switch (t) {
    case ParamType::real:
      return "real";
    case ParamType::integer:
      return "integer";
    case ParamType::boolean:
      return "bool";
    case ParamType::choice:
      return "choice";
  }
  return "real";
}

ParamSpec real_param(RealParam p) {
  return {.name = std::move(p.name),
          .type = ParamType::real,
          .default_value = p.def,
          .min = p.min,
          .max = p.max,
          .log_scale = p.spacing == Spacing::log,
          .unit = std::move(p.unit),
          .meaning = std::move(p.meaning),
          .choices = {}};
}

ParamSpec int_param(IntParam p) {
  ParamSpec s = real_param({.name = std::move(p.name),
                            .def = 0.0,
                            .min = p.min,
                            .max = p.max,
                            .spacing = p.spacing,
                            .unit = std::move(p.unit),
                            .meaning = std::move(p.meaning)});
  s.type = ParamType::integer;
  s.default_value = p.def;
  return s;
}

ParamSpec bool_param(BoolParam p) {
  return {.name = std::move(p.name),
          .type = ParamType::boolean,
          .default_value = p.def,
          .min = 0,
          .max = 0,
          .log_scale = false,
          .unit = "",
          .meaning = std::move(p.meaning),
          .choices = {}};
}

ParamSpec choice_param(ChoiceParam p) {
  return {.name = std::move(p.name),
          .type = ParamType::choice,
          .default_value = std::move(p.def),
          .min = 0,
          .max = 0,
          .log_scale = false,
          .unit = "",
          .meaning = std::move(p.meaning),
          .choices = std::move(p.choices)};
}

const char* backend_name(Backend b) {
  switch (b) {
    case Backend::cpu:
      return "cpu";
    case Backend::embree:
      return "embree";
    case Backend::vulkan:
      return "vulkan";
    case Backend::process:
      return "process";
  }
  return "cpu";
}

const char* input_name(EstimatorInput i) {
  switch (i) {
    case EstimatorInput::gbuffer:
      return "gbuffer";
    case EstimatorInput::scene_geometry:
      return "scene geometry";
    case EstimatorInput::tree_proxies:
      return "tree proxies";
  }
  return "gbuffer";
}

const ParamSpec* EstimatorInfo::find_param(const std::string& param) const {
  for (const auto& p : params)
    if (p.name == param) return &p;
  return nullptr;
}

double ParamSet::real(const std::string& name) const {
  note_read(name);
  return values_.at(name).get<double>();
}
int64_t ParamSet::integer(const std::string& name) const {
  note_read(name);
  return values_.at(name).get<int64_t>();
}
bool ParamSet::boolean(const std::string& name) const {
  note_read(name);
  return values_.at(name).get<bool>();
}
std::string ParamSet::choice(const std::string& name) const {
  note_read(name);
  return values_.at(name).get<std::string>();
}
void ParamSet::note_read(const std::string& name) const {
  std::lock_guard<std::mutex> lock(reads_->mutex);
  reads_->names.insert(name);
}
std::set<std::string> ParamSet::read_names() const {
  std::lock_guard<std::mutex> lock(reads_->mutex);
  return reads_->names;
}

namespace {

std::string range_text(const ParamSpec& p) {
  std::ostringstream os;
  if (p.type == ParamType::choice) {
    os << "one of: ";
    for (size_t i = 0; i < p.choices.size(); ++i) os << (i ? ", " : "") << p.choices[i];
  } else if (p.type == ParamType::boolean) {
    os << "true or false";
  } else {
    os << "[" << format_param_value(p.min) << ", " << format_param_value(p.max) << "]";
    if (!p.unit.empty()) os << " " << p.unit;
  }
  return os.str();
}

nlohmann::json coerce(const ParamSpec& p, const nlohmann::json& given, const std::string& where) {
  auto fail = [&](const std::string& why) -> nlohmann::json {
    throw InputError(where + ": " + p.name + "=" + format_param_value(given) + ": " + why +
                     " (allowed: " + range_text(p) + ")");
  };
  switch (p.type) {
    case ParamType::boolean: {
      if (given.is_boolean()) return given;
      if (given.is_string()) {
        const auto s = given.get<std::string>();
        if (s == "true" || s == "1" || s == "on") return true;
        if (s == "false" || s == "0" || s == "off") return false;
      }
      return fail("expected true or false");
    }
    case ParamType::choice: {
      if (!given.is_string()) return fail("expected a string");
      for (const auto& c : p.choices)
        if (c == given.get<std::string>()) return given;
      return fail("unknown choice");
    }
    case ParamType::integer:
    case ParamType::real: {
      double v = 0.0;
      if (given.is_number()) {
        v = given.get<double>();
      } else if (given.is_string()) {
        const auto s = given.get<std::string>();
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return fail("expected a number");
      } else {
        return fail("expected a number");
      }
      if (!std::isfinite(v)) return fail("expected a finite number");
      if (p.type == ParamType::integer) {
        if (v != std::floor(v)) return fail("expected an integer");
        if (v < p.min || v > p.max) return fail("out of range");
        return static_cast<int64_t>(v);
      }
      if (v < p.min || v > p.max) return fail("out of range");
      return v;
    }
  }
  return given;
}

}  // namespace

ParamSet resolve_params(const std::string& estimator, const std::vector<ParamSpec>& specs,
                        const nlohmann::json& overrides, const std::string& where) {
  nlohmann::json values = nlohmann::json::object();
  for (const auto& p : specs) values[p.name] = p.default_value;
  if (!overrides.is_null()) {
    if (!overrides.is_object()) throw InputError(where + ": expected an object of parameters");
    for (auto it = overrides.begin(); it != overrides.end(); ++it) {
      const ParamSpec* spec = nullptr;
      for (const auto& p : specs)
        if (p.name == it.key()) spec = &p;
      if (!spec) {
        std::string known;
        for (const auto& p : specs) known += (known.empty() ? "" : ", ") + p.name;
        throw InputError(where + ": unknown parameter '" + it.key() + "' for estimator " +
                         estimator + " (parameters: " + (known.empty() ? "none" : known) + ")");
      }
      values[spec->name] = coerce(*spec, it.value(), where);
    }
  }
  return ParamSet(values);
}

nlohmann::json parse_set_arguments(const std::vector<std::string>& assignments) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& a : assignments) {
    const auto eq = a.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--set: expected KEY=VALUE, got '" + a + "'");
    const std::string key = a.substr(0, eq);
    if (out.contains(key)) throw InputError("--set: '" + key + "' is given twice");
    out[key] = a.substr(eq + 1);
  }
  return out;
}

ParamSet default_params(const EstimatorInfo& info) {
  return resolve_params(info.name, info.params, nlohmann::json::object(), info.name + " defaults");
}

double EstimatorInfo::open_plane_tolerance() const {
  if (conformance.open_plane_tolerance >= 0.0) return conformance.open_plane_tolerance;
  return backend == Backend::embree ? 1e-6 : 0.05;
}

bool EstimatorInfo::warms_up() const {
  return (backend == Backend::vulkan || backend == Backend::process) && !first_run_is_warm;
}

bool EstimatorInfo::sees_enclosure() const {
  if (conformance.sees_enclosure >= 0) return conformance.sees_enclosure != 0;
  return backend == Backend::embree;
}

}  // namespace aoeval
