// Where plug-in estimators come from (CONTRACT §7) and how one becomes a registry entry.
//
// Folders, in this order: the shipped examples (<source tree>/plugins/examples), then each folder
// of $AOEVAL_PLUGINS (separated by ':'), then each --plugins DIR. A folder given is either a
// plug-in (it holds estimator.json) or a folder of plug-ins (its sub-folders that hold one, in
// name order). A plug-in whose name is a built-in's, or another plug-in's from a different folder,
// is an InputError naming both files; the same folder met twice is read once.
#pragma once

#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/plugins/plugin_manifest.h"

namespace aoeval {

// <source tree>/plugins/examples.
std::string shipped_plugins_dir();
// The folders of $AOEVAL_PLUGINS ("" entries skipped).
std::vector<std::string> env_plugin_dirs();
// The plug-in folders `dir` stands for (see above); InputError naming `dir` when it is neither.
std::vector<std::string> plugin_folders_in(const std::string& dir);

// What `aoeval estimators abi` prints: the GLSL ABI (plugin_glsl.h), then the process protocols
// (plugin_frames.h).
std::string plugin_abi_text();

// The plug-in's code version, as estimator_code_version (registry.h) gives it: "<kind>:" and 12 hex
// digits of the FNV-1a of the content (not the dates) of estimator.json and of the files it names:
// a GLSL plug-in's shaders, a process plug-in's command words that are files in its folder (its
// script, say, not /usr/bin/python3). A file it reads on its own is not seen.
std::string plugin_code_version(const PluginManifest& m);

// The registry entry of a validated manifest: backend process or vulkan, kind "process"/"glsl".
EstimatorInfo plugin_estimator(const PluginManifest& m);

// What a suite, sweep or tune calls for each estimator it will run, before its first point: a GLSL
// plug-in's shaders are compiled (and cached), so that a compile error is exit 2 before anything
// is written, not a failure halfway through the points. Nothing for other estimators.
void prepare_plugin_for_run(const EstimatorInfo& e);

}  // namespace aoeval
