// FNV-1a (Fowler, Noll, Vo), 64-bit: the one hash of aoeval's content keys (the reference cache's
// keys and image checksums, a mesh's and a scene's content hash, a GLSL plug-in's pipeline cache
// key). Not cryptographic: it names content, it does not defend against an adversary. Changing it
// changes every cache key, so its constants are fixed here once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace aoeval {

inline constexpr uint64_t kFnv1aOffset = 0xcbf29ce484222325ull;
inline constexpr uint64_t kFnv1aPrime = 0x100000001b3ull;

// Byte by byte: h = (h ^ byte) * prime.
struct Fnv1a {
  uint64_t h = kFnv1aOffset;
  void bytes(const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) {
      h ^= p[i];
      h *= kFnv1aPrime;
    }
  }
  void text(std::string_view s) { bytes(s.data(), s.size()); }
};

inline uint64_t fnv1a(std::string_view s, uint64_t start = kFnv1aOffset) {
  Fnv1a f{start};
  f.text(s);
  return f.h;
}

// One 64-bit word folded in at once, (h ^ word) * prime: combines hashes that are already FNV-1a
// values (a scene's from its meshes'), not a byte-wise FNV-1a of the word.
inline constexpr uint64_t fnv1a_fold(uint64_t h, uint64_t word) {
  return (h ^ word) * kFnv1aPrime;
}

}  // namespace aoeval
