// What a compiled compute shader declares for the host to bind, read from its SPIR-V words (the
// SPIR-V 1.3 specification's OpDecorate, OpTypePointer and OpVariable): every descriptor with its
// set, binding, kind and name, and every push-constant block. It reads the module itself rather
// than glslang's AST, so a shader taken from the SPIR-V cache is reflected the same way as one
// compiled a moment ago.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace aoeval {

enum class SpirvDescriptorKind {
  storage_image,           // image2D with a format (imageLoad / imageStore)
  sampled_image,           // texture2D
  combined_image_sampler,  // sampler2D
  sampler,                 // sampler
  uniform_texel_buffer,    // samplerBuffer
  storage_texel_buffer,    // imageBuffer
  uniform_buffer,          // a uniform block
  storage_buffer,          // a buffer block (SSBO)
  other,                   // anything else with a binding (an acceleration structure, ...)
};

// "a storage image", "a sampler2D-style combined image sampler", ...: for messages.
std::string spirv_kind_text(SpirvDescriptorKind kind);

struct SpirvDescriptor {
  std::string name;  // the variable's OpName (a block's instance name; its type's name if none)
  bool has_set = false, has_binding = false;
  uint32_t set = 0, binding = 0;
  SpirvDescriptorKind kind = SpirvDescriptorKind::other;
  uint32_t array_size = 1;    // 0 for a runtime-sized array
  uint32_t image_format = 0;  // SPIR-V ImageFormat of a storage image (0 = Unknown)
  bool non_writable = false;  // decorated NonWritable (`readonly`)
};

struct SpirvReflection {
  std::vector<SpirvDescriptor> descriptors;  // in declaration order
  std::vector<std::string> push_constants;   // names of the push-constant blocks
};

// std::invalid_argument when `words` is not a SPIR-V module (bad magic, a truncated instruction).
SpirvReflection reflect_spirv(const std::vector<uint32_t>& words);

}  // namespace aoeval
