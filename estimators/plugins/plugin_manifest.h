// Plug-in estimators (CONTRACT §7): a folder holding `estimator.json`, read and validated here into
// the same declaration a built-in estimator makes (ParamSpec table, AO definition), so that --set,
// sweeps, suites, results rows, reports and the dashboard treat it exactly like a built-in.
//
// Validation is as strict as a built-in's table (the registry test holds built-ins to the same
// rules): unknown fields, a type other than real/integer/boolean/choice, a default outside its
// range or not among its choices, an empty meaning, duplicate names, a log scale on a range that
// is not positive, a definition whose dmax names no positive numeric parameter, a falloff without
// dmax, a missing command or shader: each is an InputError "<file>: <field>: <why>" (exit 2).
// The file is held to aoeval's JSON limits (input_limits.h: nesting depth, size), and command[0]
// is resolved when read: a bare name in the plug-in folder first, then on PATH; it must be an
// executable file.
#pragma once

#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "scenes/ao_definition.h"

namespace aoeval {

enum class PluginKind { process, glsl };
const char* plugin_kind_name(PluginKind k);

// How a process plug-in's program is run (the manifest's "protocol"): `run` (the default, CONTRACT
// §7) once per frame with the files on its command line; `frames` (CONTRACT §10) once per sequence
// or still view, one JSON request line per frame on stdin (plugin_frames.h).
enum class ProcessProtocol { run, frames };
const char* process_protocol_name(ProcessProtocol p);

struct PluginManifest {
  std::string folder;  // absolute path of the plug-in folder
  std::string file;    // folder + "/estimator.json", the name every error starts with
  std::string name, summary, paper;
  PluginKind kind = PluginKind::process;
  std::vector<std::string> command;  // process: argv (command[0] resolved), run in `folder`
  std::vector<std::string> shaders;  // glsl: compute shaders (paths relative to `folder`), in order
  std::vector<ParamSpec> params;
  // definition: weighting and falloff as declared; dmax a number (infinity = null) or, when
  // dmax_param is not empty, the value of that parameter.
  Weighting weighting = Weighting::cosine;
  Falloff falloff = Falloff::none;
  double dmax = 0.0;
  std::string dmax_param;
  bool bent = false;  // outputs holds "bent": bent.X/Y/Z are read back and kept
  // The largest |AO - 1| the estimator promises on an open plane, which the registry-wide
  // conformance test holds it to; < 0: the backend's default (EstimatorInfo::conformance).
  double open_plane_tolerance = -1.0;
  double timeout_s = 120.0;  // process: its processes are killed after this long; glsl: a frame's
                             // wait ends and its Vulkan device is abandoned
  int frames = 1;            // process: the N of --frames N (frames the program times itself)
  ProcessProtocol protocol = ProcessProtocol::run;  // process only
};

// Reads and validates `folder`/estimator.json; InputError "<file>: <field>: <why>" otherwise.
PluginManifest read_plugin_manifest(const std::string& folder);

// The name a plug-in folder answers to even when its manifest is broken: estimator.json's "name"
// when it can be read as a string, else the folder's own name. Never throws.
std::string plugin_name_hint(const std::string& folder);

// The AO definition the plug-in declares, at these parameter values.
AoDefinition plugin_definition(const PluginManifest& m, const ParamSet& params);
// One line for `aoeval estimators show`: "cosine weighting, dmax = radius, falloff none".
std::string plugin_definition_doc(const PluginManifest& m);

// The parameter values a plug-in that keeps state sends for one frame: `values` with the integer
// parameter "seed" (when the manifest declares one) plus frame->seed_offset, the seed rule of
// CONTRACT §10 (k, or 0 under "seed_per_frame": false); `values` itself on a still view (null).
nlohmann::json frame_param_values(const PluginManifest& m, const nlohmann::json& values,
                                  const FrameInfo* frame);

// The shader pass names of a glsl plug-in: each shader's file stem ("ao.comp" -> "ao"), the prefix
// of its "<pass>_ms" results column.
std::vector<std::string> plugin_pass_names(const PluginManifest& m);

}  // namespace aoeval
