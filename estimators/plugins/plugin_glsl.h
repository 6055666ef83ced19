// GLSL plug-ins (CONTRACT §7): compute shaders compiled at run time with the glslang library (not
// a subprocess) and run on aoeval's Vulkan device (estimators/vulkan: lavapipe by default, a real
// GPU when present), one dispatch per shader in manifest order, a GPU timestamp span around each.
//
// The ABI (printed by `aoeval estimators abi`) is a preamble aoeval compiles in after the
// shader's #version line: storage images for the linear depth, the eye-space normals and
// positions, the previous pass's output, this pass's output, a bent-normal image and a noise
// tile, and one uniform block `aoeval` with the camera (projection, view, lens) and the
// manifest's parameters in manifest order (aoeval.params.<name>). Eye space is right-handed: x
// right, y up, the camera looking down -z (linear depth Z = -z).
//
// Compile errors are InputErrors quoting the shader's file and line (exit 2). Compiled SPIR-V is
// cached by content (a 128-bit hash of the compiler version, the preamble and the source) in
// <data cache>/spirv/, $AOEVAL_CACHE when set.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/plugins/plugin_manifest.h"

namespace aoeval {

// The ABI preamble for a plug-in's parameters (none: the fixed part only, with a comment where
// the parameters go).
std::string glsl_abi_preamble(const std::vector<ParamSpec>& params);
// The ABI, explained, with the preamble: what `aoeval estimators abi` prints.
std::string glsl_abi_text();

struct CompiledShader {
  std::vector<uint32_t> spirv;
  uint32_t local_size[3] = {1, 1, 1};
  bool from_cache = false;
};
// Compiles `source` (named `file` in messages) with the preamble for `params`; InputError
// "<file>:<line>: <message>" on a compile error.
CompiledShader compile_glsl_compute(const std::string& file, const std::string& source,
                                    const std::vector<ParamSpec>& params);

std::unique_ptr<Estimator> make_glsl_estimator(const PluginManifest& m, const ParamSet& params);

}  // namespace aoeval
