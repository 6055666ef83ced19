// The scene corpus of CONTRACT §6: scene files under scenes/corpus/, addressed by name.
#pragma once

#include <string>
#include <vector>

#include "scenes/scene.h"

namespace aoeval {

// $AOEVAL_CORPUS, else the source tree's scenes/corpus (fixed at build time).
std::string corpus_dir();

// Corpus names in a fixed order (the CONTRACT §6 order, then any other files alphabetically).
std::vector<std::string> corpus_names();

// `name_or_path` is a corpus name or a path to a scene file. The scene's `name` is the corpus name
// for corpus scenes. Unknown names are an InputError listing the corpus.
std::string resolve_scene_path(const std::string& name_or_path);
Scene load_scene(const std::string& name_or_path);
// The scene's name as results use it: the corpus name, or the file's stem.
std::string scene_display_name(const std::string& name_or_path);

}  // namespace aoeval
