// GLSL plug-ins, the host side of the ABI that the compiler and the runner share (internal to
// estimators/plugins/; the preamble's text is public, plugin_glsl.h): the binding table the
// preamble declares, the noise tile's size and the std140 bytes of the `aoeval` uniform block.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/plugins/plugin_manifest.h"

namespace aoeval {

inline constexpr int kGlslNoiseSize =
    64;  // the noise tile is kGlslNoiseSize x kGlslNoiseSize texels

// The binding table of the ABI; the preamble (glsl_abi_preamble) declares the same, in this order.
extern const std::vector<VkDescriptorType> kGlslBindings;
// The preamble's variable at each binding of kGlslBindings ("aoeval" is the uniform block).
extern const std::vector<std::string> kGlslBindingNames;

// Checks a compiled shader (`spirv`, compiled from `source`, named `file` in messages) against
// the ABI before any pipeline is built from it, by reflecting its SPIR-V (spirv_reflect.h): every
// descriptor must be the preamble's own at its binding (set 0, bindings 0..10, its type; a
// sampler2D or a buffer block at an ABI binding, a second variable there or a binding past the
// table would make the driver read a descriptor of another type: lavapipe dies of SIGBUS or
// SIGSEGV, or the shader runs on undefined data), and no push-constant block (aoeval pushes
// none). InputError "<file>:<line>: `<name>`, <kind> at set S, binding B: <why>", the line being
// where the source first names the variable (omitted when not found).
void check_glsl_abi(const std::vector<uint32_t>& spirv, const std::string& file,
                    const std::string& source);

// The size of the aoeval block of plug-in `m`, bytes (a multiple of 16).
size_t glsl_uniform_block_bytes(const PluginManifest& m);
// The aoeval block of pass `pass_index` of `passes` for frame `frame_info` (index 0 on a still
// view) of G-buffer `g`, with noise seed `seed` (also aoeval.params.seed when declared).
std::vector<uint8_t> glsl_uniform_block(const PluginManifest& m, const ParamSet& params,
                                        const FrameInfo& frame_info, int32_t seed, const GBuffer& g,
                                        int32_t pass_index, int32_t passes);

}  // namespace aoeval
