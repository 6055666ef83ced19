#include "scenes/corpus.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "base/errors.h"
#include "scenes/gltf_scene.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {
// CONTRACT §6 order; more may be added as files, listed after these.
const std::vector<std::string> kContractOrder = {"sphere-uniform", "sphere-uniform-dense",
                                                 "tree-apple",     "tree-poplar",
                                                 "tree-ground",    "grass-field",
                                                 "ecosystem",      "cornell-box",
                                                 "room",           "bunny",
                                                 "dragon",         "armadillo",
                                                 "elephant"};
}  // namespace

std::string corpus_dir() {
  if (const char* c = std::getenv("AOEVAL_CORPUS"); c && *c) return c;
  return std::string(AOEVAL_SOURCE_DIR) + "/scenes/corpus";
}

std::vector<std::string> corpus_names() {
  std::vector<std::string> others;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(corpus_dir(), ec)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".json" && ext != ".glb" && ext != ".gltf") continue;
    std::string stem = entry.path().stem().string();
    if (std::find(kContractOrder.begin(), kContractOrder.end(), stem) == kContractOrder.end())
      others.push_back(stem);
  }
  std::sort(others.begin(), others.end());
  std::vector<std::string> names;
  for (const auto& n : kContractOrder)
    if (fs::exists(fs::path(corpus_dir()) / (n + ".json"))) names.push_back(n);
  names.insert(names.end(), others.begin(), others.end());
  return names;
}

std::string resolve_scene_path(const std::string& name_or_path) {
  if (name_or_path.find('/') != std::string::npos ||
      fs::path(name_or_path).extension() == ".json" || is_gltf_path(name_or_path)) {
    std::error_code ec;  // a symlink loop or an unreadable folder is bad input, not a crash
    const bool exists = fs::exists(name_or_path, ec);
    if (ec) throw InputError(name_or_path + ": cannot read scene file (" + ec.message() + ")");
    if (!exists) throw InputError(name_or_path + ": scene file not found");
    return name_or_path;
  }
  for (const char* ext : {".json", ".glb", ".gltf"}) {
    const fs::path p = fs::path(corpus_dir()) / (name_or_path + ext);
    if (fs::exists(p)) return p.string();
  }
  std::string known;
  for (const auto& n : corpus_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("--scene: unknown scene '" + name_or_path + "' (corpus: " + known + ")");
}

Scene load_scene(const std::string& name_or_path) {
  return load_scene_file(resolve_scene_path(name_or_path));
}

std::string scene_display_name(const std::string& name_or_path) {
  return fs::path(resolve_scene_path(name_or_path)).stem().string();
}

}  // namespace aoeval
