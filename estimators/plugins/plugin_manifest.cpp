// estimator.json -> PluginManifest, field by field, every error naming the file and the field.
#include "estimators/plugins/plugin_manifest.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "base/errors.h"
#include "base/input_limits.h"

namespace aoeval {

namespace fs = std::filesystem;

const char* plugin_kind_name(PluginKind k) {
  return k == PluginKind::glsl ? "glsl" : "process";
}

const char* process_protocol_name(ProcessProtocol p) {
  return p == ProcessProtocol::frames ? "frames" : "run";
}

namespace {

using nlohmann::json;

// A value for an error message, bounded: scalars as written (at most 40 characters), containers
// by kind, so that no message walks (or copies) a large or deep value.
std::string describe(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  [[noreturn]] void fail(const std::string& field, const std::string& why) const {
    throw InputError(file_ + ": " + field + ": " + why);
  }
  const json& require(const json& object, const std::string& key, const std::string& field) const {
    const auto it = object.find(key);
    if (it == object.end()) fail(field, "missing");
    return *it;
  }
  std::string string_of(const json& v, const std::string& field, bool allow_empty = false) const {
    if (!v.is_string()) fail(field, "expected a string, got " + describe(v));
    std::string s = v.get<std::string>();
    if (!allow_empty && s.empty()) fail(field, "must not be empty");
    return s;
  }
  double number_of(const json& v, const std::string& field) const {
    if (!v.is_number()) fail(field, "expected a number, got " + describe(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(field, "expected a finite number");
    return d;
  }
  std::vector<std::string> strings_of(const json& v, const std::string& field) const {
    if (!v.is_array() || v.empty()) fail(field, "expected a non-empty array of strings");
    std::vector<std::string> out;
    for (size_t i = 0; i < v.size(); ++i)
      out.push_back(string_of(v[i], field + "[" + std::to_string(i) + "]"));
    return out;
  }
  void only_known(const json& object, const std::set<std::string>& known,
                  const std::string& field) const {
    for (const auto& [key, value] : object.items()) {
      if (known.count(key)) continue;
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(field.empty() ? key : field + "." + key, "unknown field (fields: " + list + ")");
    }
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// Estimator names appear in run names ("name/key:value/scene:..."), file names and URLs.
bool is_estimator_name(const std::string& s) {
  if (s.empty() || !std::isalnum(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!(std::islower(static_cast<unsigned char>(c)) ||
          std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.'))
      return false;
  return true;
}

ParamSpec read_param(const Reader& r, const json& p, const std::string& field) {
  if (!p.is_object()) r.fail(field, "expected an object");
  r.only_known(p, {"name", "type", "default", "min", "max", "scale", "unit", "meaning", "choices"},
               field);
  ParamSpec s;
  s.name = r.string_of(r.require(p, "name", field + ".name"), field + ".name");
  if (!is_identifier(s.name))
    r.fail(field + ".name", "\"" + s.name + "\" is not an identifier ([A-Za-z_][A-Za-z0-9_]*)");
  const std::string type = r.string_of(r.require(p, "type", field + ".type"), field + ".type");
  if (type == "real") {
    s.type = ParamType::real;
  } else if (type == "integer") {
    s.type = ParamType::integer;
  } else if (type == "boolean" || type == "bool") {
    s.type = ParamType::boolean;
  } else if (type == "choice") {
    s.type = ParamType::choice;
  } else {
    r.fail(field + ".type", "\"" + type + "\" is not one of real, integer, boolean, choice");
  }
  s.meaning = r.string_of(r.require(p, "meaning", field + ".meaning"), field + ".meaning");
  if (p.contains("unit")) s.unit = r.string_of(p["unit"], field + ".unit", true);
  const json& d = r.require(p, "default", field + ".default");
  const bool numeric = s.type == ParamType::real || s.type == ParamType::integer;
  if (!numeric) {
    for (const char* k : {"min", "max", "scale"})
      if (p.contains(k))
        r.fail(field + "." + k, std::string("only for real and integer parameters"));
  }
  if (s.type != ParamType::choice && p.contains("choices"))
    r.fail(field + ".choices", "only for choice parameters");
  switch (s.type) {
    case ParamType::boolean:
      if (!d.is_boolean()) r.fail(field + ".default", "expected true or false, got " + describe(d));
      s.default_value = d;
      break;
    case ParamType::choice: {
      s.choices = r.strings_of(r.require(p, "choices", field + ".choices"), field + ".choices");
      std::set<std::string> unique(s.choices.begin(), s.choices.end());
      if (unique.size() != s.choices.size()) r.fail(field + ".choices", "duplicate choice");
      const std::string v = r.string_of(d, field + ".default");
      if (!unique.count(v)) r.fail(field + ".default", "\"" + v + "\" is not one of the choices");
      s.default_value = v;
      break;
    }
    case ParamType::real:
    case ParamType::integer: {
      s.min = r.number_of(r.require(p, "min", field + ".min"), field + ".min");
      s.max = r.number_of(r.require(p, "max", field + ".max"), field + ".max");
      if (!(s.min <= s.max))
        r.fail(field + ".max",
               format_param_value(s.max) + " is below min " + format_param_value(s.min));
      const double v = r.number_of(d, field + ".default");
      if (v < s.min || v > s.max)
        r.fail(field + ".default", format_param_value(d) + " is outside [" +
                                       format_param_value(s.min) + ", " +
                                       format_param_value(s.max) + "]");
      if (s.type == ParamType::integer) {
        if (v != std::floor(v))
          r.fail(field + ".default", "expected an integer, got " + describe(d));
        if (s.min != std::floor(s.min) || s.max != std::floor(s.max))
          r.fail(field + ".min", "an integer parameter's range must have integer ends");
        s.default_value = static_cast<int64_t>(v);
      } else {
        s.default_value = v;
      }
      if (p.contains("scale")) {
        const std::string scale = r.string_of(p["scale"], field + ".scale");
        if (scale == "log") {
          if (!(s.min > 0.0))
            r.fail(field + ".scale", "log scale needs a positive range (min > 0)");
          s.log_scale = true;
        } else if (scale != "lin" && scale != "linear") {
          r.fail(field + ".scale", "\"" + scale + "\" is not lin or log");
        }
      }
      break;
    }
  }
  return s;
}

void read_definition(const Reader& r, const json& d, PluginManifest& m) {
  const std::string field = "definition";
  if (!d.is_object()) r.fail(field, "expected an object");
  r.only_known(d, {"weighting", "dmax", "falloff"}, field);
  const std::string w =
      r.string_of(r.require(d, "weighting", field + ".weighting"), field + ".weighting");
  if (w == "cosine")
    m.weighting = Weighting::cosine;
  else if (w == "uniform")
    m.weighting = Weighting::uniform;
  else
    r.fail(field + ".weighting", "\"" + w + "\" is not cosine or uniform");
  const std::string f =
      d.contains("falloff") ? r.string_of(d["falloff"], field + ".falloff") : std::string("none");
  try {
    m.falloff = parse_falloff(f, field + ".falloff");  // CONTRACT §3, power:K included
  } catch (const InputError&) {
    r.fail(field + ".falloff",
           "\"" + f + "\" is not none, linear, sqrt, exp or power:K (K a positive number)");
  }
  const json dmax = d.contains("dmax") ? d["dmax"] : json(nullptr);
  if (dmax.is_null()) {
    m.dmax = std::numeric_limits<double>::infinity();
  } else if (dmax.is_string()) {
    m.dmax_param = dmax.get<std::string>();
    const ParamSpec* p = nullptr;
    for (const auto& s : m.params)
      if (s.name == m.dmax_param) p = &s;
    if (!p) r.fail(field + ".dmax", "\"" + m.dmax_param + "\" names no parameter");
    if ((p->type != ParamType::real && p->type != ParamType::integer) || !(p->min > 0.0))
      r.fail(field + ".dmax", "parameter \"" + m.dmax_param +
                                  "\" must be real or integer with a positive range (min > 0)");
  } else {
    m.dmax = r.number_of(dmax, field + ".dmax");
    if (!(m.dmax > 0.0)) r.fail(field + ".dmax", "must be positive (null = unbounded)");
  }
  if (m.falloff != Falloff::none && m.dmax_param.empty() && !std::isfinite(m.dmax))
    r.fail(field + ".falloff", "falloff " + f + " needs a finite dmax");
}

bool is_executable_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && access(p.c_str(), X_OK) == 0;
}

// command[0] -> the program that will run, checked now rather than as an exit status 127 later: a
// path with '/' is relative to the plug-in folder; a bare name is looked up in the plug-in folder
// first (so ["prog.sh"] runs the folder's prog.sh), then on PATH.
std::string resolve_command(const Reader& r, const fs::path& folder, const std::string& program) {
  const std::string field = "command[0]";
  auto checked = [&](const fs::path& p) {
    if (!is_executable_file(p))
      r.fail(field, p.string() + " is not an executable file (chmod +x it, or name its " +
                        "interpreter first: [\"python3\", \"" + program + "\"])");
    return p.string();
  };
  if (program.find('/') != std::string::npos) return checked((folder / program).lexically_normal());
  std::error_code ec;
  if (fs::exists(folder / program, ec)) return checked(folder / program);
  const char* env = std::getenv("PATH");
  const std::string path = env ? env : "/usr/local/bin:/usr/bin:/bin";
  for (size_t start = 0; start <= path.size();) {
    const size_t end = std::min(path.find(':', start), path.size());
    const fs::path candidate =
        fs::path(end > start ? path.substr(start, end - start) : ".") / program;
    if (is_executable_file(candidate)) return program;  // execvp finds the same one
    start = end + 1;
  }
  r.fail(field,
         "\"" + program + "\" is neither a file in the plug-in folder nor a program on PATH");
}

// estimator.json's text -> JSON (comments allowed), held to the limits of every other JSON input
// (input_limits.h): at most kMaxJsonBytes, nested at most kMaxJsonDepth deep (deeper values are
// dropped while parsing, so nothing recursive ever walks them), and a number no double holds
// (1e400) named by its key instead of nlohmann's exception text.
// With `truncated`, a too-deep document is no error: *truncated is set and the value returned
// without its deeper parts (what plugin_name_hint needs of a broken manifest).
json parse_manifest_json(const std::string& file, const std::string& text,
                         bool* truncated = nullptr) {
  if (text.size() > kMaxJsonBytes)
    throw InputError(file + ": " + std::to_string(text.size()) + " bytes, more than the limit of " +
                     std::to_string(kMaxJsonBytes));
  bool too_deep = false;
  std::string last_key = "(top level)";
  const json::parser_callback_t check = [&](int depth, json::parse_event_t event, json& value) {
    if (depth > kMaxJsonDepth) too_deep = true;
    if (event == json::parse_event_t::key && depth <= kMaxJsonDepth && value.is_string())
      last_key = value.get<std::string>();
    return depth <= kMaxJsonDepth;  // drops only the too-deep parts
  };
  json j;
  try {
    j = json::parse(text, check, true, /*ignore_comments=*/true);
  } catch (const json::parse_error& e) {
    // nlohmann's own words without its "[json.exception.parse_error.101] " tag.
    std::string what = e.what();
    if (const auto tag = what.find("] "); tag != std::string::npos) what = what.substr(tag + 2);
    throw InputError(file + ": not JSON: " + what);
  } catch (const json::out_of_range&) {
    // Raised only for a number that overflows a double (406), inside the value of `last_key`.
    throw InputError(file + ": " + last_key + ": a number too large for a double");
  }
  if (truncated) *truncated = too_deep;
  if (too_deep && !truncated)
    throw InputError(file + ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  return j;
}

}  // namespace

PluginManifest read_plugin_manifest(const std::string& folder_text) {
  std::error_code ec;
  const fs::path folder = fs::absolute(folder_text, ec).lexically_normal();
  PluginManifest m;
  m.folder = folder.string();
  if (!m.folder.empty() && m.folder.back() == '/') m.folder.pop_back();
  m.file = (folder / "estimator.json").string();
  const Reader r(m.file);
  std::ifstream in(m.file);
  if (!in) throw InputError(m.file + ": cannot read (a plug-in folder holds estimator.json)");
  std::stringstream text;
  text << in.rdbuf();
  const json j = parse_manifest_json(m.file, text.str());
  if (!j.is_object()) r.fail("(top level)", "expected an object");
  r.only_known(j,
               {"name", "summary", "paper", "kind", "command", "shaders", "params", "definition",
                "outputs", "timeout_s", "frames", "protocol", "open_plane_tolerance"},
               "");
  m.name = r.string_of(r.require(j, "name", "name"), "name");
  if (!is_estimator_name(m.name))
    r.fail("name", "\"" + m.name + "\" must be lower-case letters, digits, '-', '_' or '.'");
  m.summary = r.string_of(r.require(j, "summary", "summary"), "summary");
  m.paper = j.contains("paper") ? r.string_of(j["paper"], "paper", true) : "";
  const std::string kind = r.string_of(r.require(j, "kind", "kind"), "kind");
  if (kind == "process") {
    m.kind = PluginKind::process;
    m.command = r.strings_of(r.require(j, "command", "command"), "command");
    if (j.contains("shaders")) r.fail("shaders", "only for kind glsl");
  } else if (kind == "glsl") {
    m.kind = PluginKind::glsl;
    m.shaders = r.strings_of(r.require(j, "shaders", "shaders"), "shaders");
    if (j.contains("command")) r.fail("command", "only for kind process");
    if (j.contains("frames")) r.fail("frames", "only for kind process");
    if (j.contains("protocol")) r.fail("protocol", "only for kind process");
    std::set<std::string> passes;
    for (size_t i = 0; i < m.shaders.size(); ++i) {
      const std::string field = "shaders[" + std::to_string(i) + "]";
      const fs::path shader = folder / m.shaders[i];
      if (!fs::is_regular_file(shader, ec)) r.fail(field, shader.string() + " does not exist");
      const std::string pass = fs::path(m.shaders[i]).stem().string();
      // The pass's results column is "<pass>_ms"; "total_ms" is the whole frame's.
      if (!is_identifier(pass) || pass == "total" || pass == "precompute" || pass == "time")
        r.fail(field, "pass name \"" + pass +
                          "\" (the file's stem) must be an identifier other than total, "
                          "precompute and time");
      if (!passes.insert(pass).second) r.fail(field, "two shaders named \"" + pass + "\"");
    }
  } else {
    r.fail("kind", "\"" + kind + "\" is not process or glsl");
  }
  if (j.contains("params")) {
    const json& ps = j["params"];
    if (!ps.is_array()) r.fail("params", "expected an array");
    std::set<std::string> names;
    for (size_t i = 0; i < ps.size(); ++i) {
      const std::string field = "params[" + std::to_string(i) + "]";
      ParamSpec s = read_param(r, ps[i], field);
      if (!names.insert(s.name).second)
        r.fail(field + ".name", "duplicate name \"" + s.name + "\"");
      m.params.push_back(std::move(s));
    }
  }
  read_definition(r, r.require(j, "definition", "definition"), m);
  if (j.contains("outputs")) {
    const std::vector<std::string> outputs = r.strings_of(j["outputs"], "outputs");
    bool ao = false;
    for (size_t i = 0; i < outputs.size(); ++i) {
      if (outputs[i] == "AO")
        ao = true;
      else if (outputs[i] == "bent")
        m.bent = true;
      else
        r.fail("outputs[" + std::to_string(i) + "]", "\"" + outputs[i] + "\" is not AO or bent");
    }
    if (!ao) r.fail("outputs", "must hold \"AO\"");
  }
  if (j.contains("timeout_s")) {
    m.timeout_s = r.number_of(j["timeout_s"], "timeout_s");
    if (!(m.timeout_s > 0.0) || m.timeout_s > 86400.0) r.fail("timeout_s", "must be in (0, 86400]");
  }
  if (j.contains("open_plane_tolerance")) {
    m.open_plane_tolerance = r.number_of(j["open_plane_tolerance"], "open_plane_tolerance");
    if (!(m.open_plane_tolerance >= 0.0 && m.open_plane_tolerance <= 1.0))
      r.fail("open_plane_tolerance", "must be in [0, 1]");
  }
  if (j.contains("frames")) {
    const double f = r.number_of(j["frames"], "frames");
    if (f != std::floor(f) || f < 1 || f > 10000)
      r.fail("frames", "must be an integer in [1, 10000]");
    m.frames = static_cast<int>(f);
  }
  if (j.contains("protocol")) {
    const std::string protocol = r.string_of(j["protocol"], "protocol");
    if (protocol == "frames")
      m.protocol = ProcessProtocol::frames;
    else if (protocol != "run")
      r.fail("protocol", "\"" + protocol +
                             "\" is not run (once per frame, the default) or frames "
                             "(one process, a JSON line per frame on stdin)");
    // A frames program is sent each frame once and times it itself (AO.exr.timing.json).
    if (m.protocol == ProcessProtocol::frames && j.contains("frames"))
      r.fail("frames",
             "only for \"protocol\": \"run\" (a frames program gets one request per "
             "frame)");
  }
  // Last: the fields' own errors come first, then whether the program is there to run.
  if (m.kind == PluginKind::process) m.command[0] = resolve_command(r, folder, m.command[0]);
  return m;
}

std::string plugin_name_hint(const std::string& folder) {
  std::error_code ec;
  const fs::path path = fs::absolute(folder, ec).lexically_normal();
  std::string name = (path.has_filename() ? path : path.parent_path()).filename().string();
  try {
    std::ifstream in(path / "estimator.json");
    std::stringstream text;
    text << in.rdbuf();
    bool truncated = false;
    const json j = parse_manifest_json("", text.str(), &truncated);
    if (j.is_object() && j.contains("name") && j["name"].is_string() &&
        !j["name"].get<std::string>().empty())
      name = j["name"].get<std::string>();
  } catch (const std::exception&) {
    // Unreadable: the folder's name stands for it.
  }
  return name;
}

AoDefinition plugin_definition(const PluginManifest& m, const ParamSet& params) {
  AoDefinition d;
  d.weighting = m.weighting;
  d.falloff = m.falloff;
  d.dmax = m.dmax_param.empty() ? m.dmax : params.json().at(m.dmax_param).get<double>();
  return d;
}

std::string plugin_definition_doc(const PluginManifest& m) {
  std::string dmax = !m.dmax_param.empty()   ? m.dmax_param
                     : std::isfinite(m.dmax) ? format_param_value(m.dmax)
                                             : "unbounded";
  return std::string(weighting_name(m.weighting)) + " weighting, dmax = " + dmax + ", falloff " +
         falloff_name(m.falloff) + " (declared by the plug-in's estimator.json)";
}

nlohmann::json frame_param_values(const PluginManifest& m, const nlohmann::json& values,
                                  const FrameInfo* frame) {
  nlohmann::json out = values;
  if (!frame || frame->seed_offset == 0) return out;
  for (const ParamSpec& p : m.params)
    if (p.name == "seed" && p.type == ParamType::integer && out.contains("seed"))
      out["seed"] = out["seed"].get<int64_t>() + static_cast<int64_t>(frame->seed_offset);
  return out;
}

std::vector<std::string> plugin_pass_names(const PluginManifest& m) {
  std::vector<std::string> names;
  for (const auto& s : m.shaders) names.push_back(fs::path(s).stem().string());
  return names;
}

}  // namespace aoeval
