#include "estimators/registry.h"

#include <filesystem>
#include <iostream>
#include <map>

#include "base/errors.h"
#include "estimators/code_versions.h"  // generated: code_version::<folder>
#include "estimators/constant/constant.h"
#include "estimators/gtao/gtao.h"
#include "estimators/hbao_split/hbao_split.h"
#include "estimators/hbao_split/hbao_vulkan.h"
#include "estimators/obscurances/obscurances.h"
#include "estimators/plugins/plugin_registry.h"
#include "estimators/raymarch_ssao/raymarch_ssao.h"
#include "estimators/raytraced/raytraced.h"
#include "estimators/reeves_blau/reeves_blau.h"
#include "estimators/rtao/rtao.h"
#include "estimators/shadowmap_ao/shadowmap_ao.h"
#include "estimators/tree_hegeman/tree_hegeman.h"
#include "estimators/tree_volume/tree_volume.h"
#include "estimators/vertex_baked/vertex_baked.h"
#include "estimators/vulkan/vk_context.h"

namespace aoeval {

namespace {

// A plug-in folder that could not be read: skipped with a warning, and an error only for a
// command that asks for it by `name` (its declared name, else the folder's name).
struct BrokenPlugin {
  std::string name, folder, error;
  bool said = false;  // its warning printed, or held back for the error of asking for it
};

struct Registry {
  std::deque<EstimatorInfo> entries;  // grows; its elements never move
  std::vector<BrokenPlugin> broken = {};
  size_t builtins = 0;
  bool default_plugins_read = false;
};

// Every estimator's code version by name (estimator_code_version).
std::map<std::string, std::string>& code_versions() {
  static std::map<std::string, std::string> versions;
  return versions;
}

// A built-in, its folder's code version (code_versions.h) recorded.
EstimatorInfo with_code(const char* version, EstimatorInfo info) {
  code_versions()[info.name] = std::string("built-in:") + version;
  return info;
}

Registry& registry_storage() {
  // One line per estimator. The calls reference each folder's symbols directly, so the linker
  // keeps them all; v::<folder> is the hash of that folder's code.
  namespace v = code_version;
  // clang-format off
  static Registry registry{{
      with_code(v::constant, constant_estimator()),
      with_code(v::raytraced, raytraced_estimator()),
      with_code(v::rtao, rtao_estimator()),
      with_code(v::obscurances, obscurances_estimator()),
      with_code(v::vertex_baked, vertex_baked_estimator()),
      with_code(v::tree_hegeman, tree_sphere_estimator()),
      with_code(v::tree_hegeman, tree_ellipsoid_estimator()),
      with_code(v::tree_hegeman, tree_shells_estimator()),
      with_code(v::tree_volume, tree_volume_estimator()),
      with_code(v::reeves_blau, reeves_blau_estimator()),
      with_code(v::hbao_split, hbao_split_estimator()),
      with_code(v::hbao_split, hbao_split_cpu_estimator()),
      with_code(v::raymarch_ssao, raymarch_ssao_estimator()),
      with_code(v::gtao, gtao_estimator()),
      with_code(v::gtao, gtao_cpu_estimator()),
      with_code(v::shadowmap_ao, shadowmap_ao_estimator()),
  }};
  // clang-format on
  if (registry.builtins == 0) registry.builtins = registry.entries.size();
  return registry;
}

void add_plugin_folder(Registry& r, const std::string& folder) {
  PluginManifest m = read_plugin_manifest(folder);
  for (size_t i = 0; i < r.entries.size(); ++i) {
    const EstimatorInfo& e = r.entries[i];
    if (e.name != m.name) continue;
    if (e.folder == m.folder) return;  // the same plug-in met twice
    throw InputError(m.file + ": name: \"" + m.name + "\" is already " +
                     (i < r.builtins ? "a built-in estimator" : "the plug-in of " + e.folder));
  }
  r.entries.push_back(plugin_estimator(m));
  code_versions()[m.name] = plugin_code_version(m);
}

// One broken plug-in must not take the others, or the built-ins, down (issue 28): its error is
// kept, to be a warning naming the folder (say_broken_plugins) or the error of a command that asks
// for it.
void add_plugin_folder_or_warn(Registry& r, const std::string& folder) {
  try {
    add_plugin_folder(r, folder);
  } catch (const InputError& e) {
    const std::string absolute = std::filesystem::absolute(folder).lexically_normal().string();
    for (const auto& b : r.broken)
      if (b.folder == absolute) return;  // warned once
    r.broken.push_back({plugin_name_hint(folder), absolute, e.what()});
  }
}

// The warnings of the broken plug-ins not yet said, except `asked`'s: a command that asks for a
// broken plug-in says why once, as its error (find_estimator), not also as a warning before it.
void say_broken_plugins(Registry& r, const std::string& asked) {
  for (BrokenPlugin& b : r.broken) {
    if (b.said) continue;
    b.said = true;
    if (b.name == asked) continue;
    std::cerr << "aoeval: warning: plug-in \"" << b.name << "\" (" << b.folder
              << ") is skipped: " << b.error << "\n";
  }
}

Registry& loaded_registry() {
  Registry& r = registry_storage();
  if (!r.default_plugins_read) {
    r.default_plugins_read = true;
    // The shipped examples, then $AOEVAL_PLUGINS (CONTRACT §7).
    std::vector<std::string> dirs = {shipped_plugins_dir()};
    for (const auto& d : env_plugin_dirs()) dirs.push_back(d);
    for (const auto& d : dirs) {
      try {
        for (const auto& folder : plugin_folders_in(d)) add_plugin_folder_or_warn(r, folder);
      } catch (const InputError& e) {  // an $AOEVAL_PLUGINS entry that is no plug-in folder
        std::cerr << "aoeval: warning: $AOEVAL_PLUGINS: " << e.what() << "\n";
      }
    }
  }
  return r;
}

}  // namespace

const std::deque<EstimatorInfo>& estimator_registry() {
  Registry& r = loaded_registry();
  say_broken_plugins(r, "");
  return r.entries;
}

void add_plugin_dir(const std::string& dir) {
  Registry& r = loaded_registry();
  for (const auto& folder : plugin_folders_in(dir)) add_plugin_folder_or_warn(r, folder);
}

const EstimatorInfo& find_estimator(const std::string& name) {
  std::string known;
  Registry& r = loaded_registry();
  say_broken_plugins(r, name);
  for (const BrokenPlugin& b : r.broken)
    if (b.name == name)
      throw InputError("--estimator: plug-in \"" + name + "\" cannot be used: " + b.error);
  for (const auto& e : r.entries) {
    if (e.name == name) return e;
    known += (known.empty() ? "" : ", ") + e.name;
  }
  throw InputError("--estimator: unknown estimator '" + name + "' (estimators: " + known + ")");
}

std::string estimator_code_version(const EstimatorInfo& e) {
  const auto it = code_versions().find(e.name);
  return it == code_versions().end() ? "" : it->second;
}

std::string backend_device(Backend b) {
  if (b != Backend::vulkan) return "";
  const vk::Context* context = vk::shared_context();
  return context ? context->device_description() : "";
}

}  // namespace aoeval
