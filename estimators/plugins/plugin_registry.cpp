#include "estimators/plugins/plugin_registry.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/hash.h"
#include "estimators/plugins/plugin_frames.h"
#include "estimators/plugins/plugin_glsl.h"
#include "estimators/plugins/plugin_process.h"

namespace aoeval {

namespace fs = std::filesystem;

std::string shipped_plugins_dir() {
  return std::string(AOEVAL_SOURCE_DIR) + "/plugins/examples";
}

std::vector<std::string> env_plugin_dirs() {
  std::vector<std::string> dirs;
  const char* env = std::getenv("AOEVAL_PLUGINS");
  if (!env) return dirs;
  std::string text = env;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(':', start), text.size());
    if (end > start) dirs.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return dirs;
}

std::vector<std::string> plugin_folders_in(const std::string& dir) {
  std::error_code ec;
  if (fs::is_regular_file(fs::path(dir) / "estimator.json", ec)) return {dir};
  if (!fs::is_directory(dir, ec)) throw InputError("plug-in folder " + dir + ": not a folder");
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    // Its own error code: a sub-folder without a manifest (a run's output folder beside the
    // plug-ins, say) reports "no such file" through it, which is an answer, not a listing error.
    std::error_code no_manifest;
    if (entry.is_directory() && fs::is_regular_file(entry.path() / "estimator.json", no_manifest))
      found.push_back(entry.path().string());
  }
  if (ec) throw InputError("plug-in folder " + dir + ": cannot list: " + ec.message());
  if (found.empty())
    throw InputError("plug-in folder " + dir + ": holds no estimator.json, nor do its sub-folders");
  std::sort(found.begin(), found.end());
  return found;
}

namespace {
// A plug-in receives every declared parameter at once (the params JSON of a process, the uniform
// block of a shader), so each is read here through its typed accessor: the run-time settings are
// then provably the table's, as the registry-wide defaults test checks for built-ins.
void read_every_param(const PluginManifest& m, const ParamSet& p) {
  for (const ParamSpec& spec : m.params) {
    switch (spec.type) {
      case ParamType::real:
        p.real(spec.name);
        break;
      case ParamType::integer:
        p.integer(spec.name);
        break;
      case ParamType::boolean:
        p.boolean(spec.name);
        break;
      case ParamType::choice:
        p.choice(spec.name);
        break;
    }
  }
}
}  // namespace

std::string plugin_abi_text() {
  return glsl_abi_text() + "\n" + process_protocol_text();
}

void prepare_plugin_for_run(const EstimatorInfo& e) {
  if (e.kind != plugin_kind_name(PluginKind::glsl)) return;
  compile_glsl_plugin(read_plugin_manifest(e.folder));
}

std::string plugin_code_version(const PluginManifest& m) {
  std::vector<std::string> files = {"estimator.json"};
  for (const auto& s : m.shaders) files.push_back(s);
  std::error_code ec;
  for (const auto& word : m.command) {
    const fs::path p = fs::path(word).is_absolute() ? fs::path(word) : fs::path(m.folder) / word;
    const std::string rel = p.lexically_normal().lexically_relative(m.folder).string();
    if (!rel.empty() && rel.rfind("..", 0) != 0 && fs::is_regular_file(p, ec)) files.push_back(rel);
  }
  Fnv1a h;
  for (const auto& f : files) {
    std::ifstream in(fs::path(m.folder) / f, std::ios::binary);
    std::ostringstream content;
    if (in.is_open()) content << in.rdbuf();
    h.text(f);
    h.text(std::string(1, '\0'));
    h.text(in.is_open() ? content.str() : std::string("(unreadable)"));
    h.text(std::string(1, '\0'));
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h.h));
  return std::string(plugin_kind_name(m.kind)) + ":" + std::string(hex, 12);
}

EstimatorInfo plugin_estimator(const PluginManifest& m) {
  EstimatorInfo info;
  info.name = m.name;
  info.summary = m.summary;
  info.paper = m.paper;
  info.conformance.open_plane_tolerance = m.open_plane_tolerance;
  info.kind = plugin_kind_name(m.kind);
  info.folder = m.folder;
  info.backend = m.kind == PluginKind::glsl ? Backend::vulkan : Backend::process;
  info.inputs = {EstimatorInput::gbuffer};
  info.params = m.params;
  info.definition_doc = plugin_definition_doc(m);
  info.definition = [m](const ParamSet& p) { return plugin_definition(m, p); };
  // Over a sequence (CONTRACT §10): a GLSL plug-in's instance keeps its device and its last output
  // (aoeval_history) from frame to frame, and a "protocol": "frames" process its program; both
  // apply the seed rule themselves. A per-run process starts afresh each frame with seed + k.
  info.keeps_state = m.kind == PluginKind::glsl || m.protocol == ProcessProtocol::frames;
  if (m.kind == PluginKind::glsl) {
    info.create = [m](const ParamSet& p) {
      read_every_param(m, p);
      return make_glsl_estimator(m, p);
    };
  } else {
    info.create = [m](const ParamSet& p) {
      read_every_param(m, p);
      return m.protocol == ProcessProtocol::frames ? make_frames_process_estimator(m, p)
                                                   : make_process_estimator(m, p);
    };
  }
  return info;
}

}  // namespace aoeval
