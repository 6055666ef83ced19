// GLSL plug-ins (CONTRACT §7): compute shaders compiled at run time with the glslang library (not
// a subprocess) and run on aoeval's Vulkan device (estimators/vulkan: lavapipe by default, a real
// GPU when present), one dispatch per shader in manifest order, a GPU timestamp span around each.
// They use a Vulkan context of their own, so that a frame past the manifest's timeout_s can be
// given up with its device (a skipped row) and the next frame gets a new one.
//
// The ABI (printed by `aoeval estimators abi`) is a preamble aoeval compiles in after the
// shader's #version line: storage images for the linear depth, the eye-space normals and
// positions, the previous pass's output, this pass's output, a bent-normal image and a noise
// tile, and one uniform block `aoeval` with the camera (projection, view, lens) and the
// manifest's parameters in manifest order (aoeval.params.<name>). Eye space is right-handed: x
// right, y up, the camera looking down -z (linear depth Z = -z).
//
// Compile errors are InputErrors quoting the shader's file and line (exit 2), and so is a shader
// whose descriptors or push constants break the ABI (check_glsl_abi, on every compiled or cached
// SPIR-V before a pipeline is built). Compiled SPIR-V is
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

// lavapipe (Mesa 22.3's CPU device, aoeval's default) stops loops after this many iterations per
// invocation, all its loops counted together (one limiter per invocation; measured: two loops of
// 40,000 run 65,534 in all, 300 x 300 nested ones 65,100), without an error: more is cut short
// and an endless loop "finishes".
inline constexpr int64_t kLavapipeLoopCap = 65535;

struct CompiledShader {
  std::vector<uint32_t> spirv;
  uint32_t local_size[3] = {1, 1, 1};
  bool from_cache = false;
};
// Compiles `source` (named `file` in messages) with the preamble for `params`; InputError
// "<file>:<line>: <message>" on a compile error.
CompiledShader compile_glsl_compute(const std::string& file, const std::string& source,
                                    const std::vector<ParamSpec>& params);

struct PassShader {
  std::string name;  // the shader's stem, the pass name
  CompiledShader code;
};
// Every shader of a glsl plug-in, compiled (through the SPIR-V cache), in manifest order.
std::vector<PassShader> compile_glsl_plugin(const PluginManifest& m);

// What in a shader's SPIR-V lavapipe's loop cap can cut short, one phrase each: an integer constant
// above kLavapipeLoopCap compared with something (a loop bound, most likely), a loop with no test
// of its own (while (true), for (;;): endless unless a break leaves it). Empty when nothing is
// seen; a bound computed at run time is not seen.
std::vector<std::string> lavapipe_loop_risks(const std::vector<uint32_t>& spirv);

std::unique_ptr<Estimator> make_glsl_estimator(const PluginManifest& m, const ParamSet& params);

}  // namespace aoeval
