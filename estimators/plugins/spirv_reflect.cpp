#include "estimators/plugins/spirv_reflect.h"

#include <map>
#include <set>
#include <stdexcept>

namespace aoeval {

namespace {

// SPIR-V 1.3 specification, sections 3.32 (opcodes), 3.20 (decorations), 3.7 (storage classes),
// 3.8 (Dim).
constexpr uint32_t kMagic = 0x07230203;
constexpr uint32_t kOpName = 5, kOpDecorate = 71, kOpTypeImage = 25, kOpTypeSampler = 26,
                   kOpTypeSampledImage = 27, kOpTypeArray = 28, kOpTypeRuntimeArray = 29,
                   kOpTypePointer = 32, kOpConstant = 43, kOpVariable = 59;
constexpr uint32_t kBufferBlock = 3, kNonWritable = 24, kBinding = 33, kDescriptorSet = 34;
constexpr uint32_t kUniformConstant = 0, kUniform = 2, kPushConstant = 9, kStorageBuffer = 12;
constexpr uint32_t kDimBuffer = 5;

std::string literal_string(const uint32_t* w, uint32_t count) {
  std::string s;
  for (uint32_t k = 0; k < count; ++k)
    for (int b = 0; b < 4; ++b) {
      const char c = static_cast<char>((w[k] >> (8 * b)) & 0xffu);
      if (c == '\0') return s;
      s += c;
    }
  return s;
}

struct Image {
  uint32_t dim = 0, sampled = 0, format = 0;
};

}  // namespace

std::string spirv_kind_text(SpirvDescriptorKind kind) {
  switch (kind) {
    case SpirvDescriptorKind::storage_image:
      return "a storage image (image2D)";
    case SpirvDescriptorKind::sampled_image:
      return "a sampled image (texture2D)";
    case SpirvDescriptorKind::combined_image_sampler:
      return "a combined image sampler (sampler2D)";
    case SpirvDescriptorKind::sampler:
      return "a sampler";
    case SpirvDescriptorKind::uniform_texel_buffer:
      return "a uniform texel buffer (samplerBuffer)";
    case SpirvDescriptorKind::storage_texel_buffer:
      return "a storage texel buffer (imageBuffer)";
    case SpirvDescriptorKind::uniform_buffer:
      return "a uniform block";
    case SpirvDescriptorKind::storage_buffer:
      return "a buffer block (SSBO)";
    case SpirvDescriptorKind::other:
      break;
  }
  return "a descriptor of another kind";
}

SpirvReflection reflect_spirv(const std::vector<uint32_t>& words) {
  if (words.size() < 5 || words[0] != kMagic)
    throw std::invalid_argument("not a SPIR-V module (no magic number)");
  std::map<uint32_t, std::string> names;
  std::map<uint32_t, std::set<uint32_t>> flags;                // id -> decorations without operand
  std::map<uint32_t, uint32_t> bindings, sets;                 // id -> operand
  std::map<uint32_t, Image> images;                            // OpTypeImage
  std::set<uint32_t> samplers;                                 // OpTypeSampler
  std::map<uint32_t, uint32_t> sampled_images;                 // OpTypeSampledImage -> image
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> arrays;    // -> element, length (0: runtime)
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> pointers;  // -> storage class, pointee
  std::map<uint32_t, uint32_t> constants;                      // 32-bit OpConstant values
  struct Variable {
    uint32_t id, type, storage;
  };
  std::vector<Variable> variables;
  for (size_t i = 5; i < words.size();) {
    const uint32_t count = words[i] >> 16, op = words[i] & 0xffffu;
    if (count == 0 || i + count > words.size())
      throw std::invalid_argument("SPIR-V instruction at word " + std::to_string(i) +
                                  " runs past the module's end");
    const uint32_t* w = &words[i];
    if (op == kOpName && count >= 3) {
      names[w[1]] = literal_string(w + 2, count - 2);
    } else if (op == kOpDecorate && count >= 3) {
      if (w[2] == kBinding && count >= 4)
        bindings[w[1]] = w[3];
      else if (w[2] == kDescriptorSet && count >= 4)
        sets[w[1]] = w[3];
      else
        flags[w[1]].insert(w[2]);
    } else if (op == kOpTypeImage && count >= 9) {
      images[w[1]] = {w[3], w[7], w[8]};
    } else if (op == kOpTypeSampler && count >= 2) {
      samplers.insert(w[1]);
    } else if (op == kOpTypeSampledImage && count >= 3) {
      sampled_images[w[1]] = w[2];
    } else if (op == kOpTypeArray && count >= 4) {
      arrays[w[1]] = {w[2], constants.count(w[3]) ? constants[w[3]] : 0};
    } else if (op == kOpTypeRuntimeArray && count >= 3) {
      arrays[w[1]] = {w[2], 0};
    } else if (op == kOpTypePointer && count >= 4) {
      pointers[w[1]] = {w[2], w[3]};
    } else if (op == kOpConstant && count == 4) {
      constants[w[2]] = w[3];
    } else if (op == kOpVariable && count >= 4) {
      variables.push_back({w[2], w[1], w[3]});
    }
    i += count;
  }
  SpirvReflection r;
  for (const Variable& v : variables) {
    if (v.storage != kUniformConstant && v.storage != kUniform && v.storage != kPushConstant &&
        v.storage != kStorageBuffer)
      continue;
    const auto ptr = pointers.find(v.type);
    uint32_t type = ptr != pointers.end() ? ptr->second.second : 0;
    std::string name = names.count(v.id) ? names[v.id] : "";
    if (v.storage == kPushConstant) {
      r.push_constants.push_back(!name.empty() ? name : names[type]);
      continue;
    }
    SpirvDescriptor d;
    d.has_set = sets.count(v.id) > 0;
    d.has_binding = bindings.count(v.id) > 0;
    d.set = d.has_set ? sets[v.id] : 0;
    d.binding = d.has_binding ? bindings[v.id] : 0;
    d.non_writable = flags[v.id].count(kNonWritable) > 0;
    if (const auto a = arrays.find(type); a != arrays.end()) {
      d.array_size = a->second.second;
      type = a->second.first;
    }
    d.name = !name.empty() ? name : names[type];
    if (v.storage == kStorageBuffer || (v.storage == kUniform && flags[type].count(kBufferBlock))) {
      d.kind = SpirvDescriptorKind::storage_buffer;
    } else if (v.storage == kUniform) {
      d.kind = SpirvDescriptorKind::uniform_buffer;
    } else if (samplers.count(type)) {
      d.kind = SpirvDescriptorKind::sampler;
    } else if (sampled_images.count(type)) {
      const Image& im = images[sampled_images[type]];
      d.kind = im.dim == kDimBuffer ? SpirvDescriptorKind::uniform_texel_buffer
                                    : SpirvDescriptorKind::combined_image_sampler;
    } else if (const auto im = images.find(type); im != images.end()) {
      const bool storage = im->second.sampled == 2, buffer = im->second.dim == kDimBuffer;
      d.kind = storage ? (buffer ? SpirvDescriptorKind::storage_texel_buffer
                                 : SpirvDescriptorKind::storage_image)
                       : (buffer ? SpirvDescriptorKind::uniform_texel_buffer
                                 : SpirvDescriptorKind::sampled_image);
      d.image_format = im->second.format;
    }
    r.descriptors.push_back(std::move(d));
  }
  return r;
}

}  // namespace aoeval
