// A glTF 2.0 file (.gltf with its buffers, or .glb) opened for reading: the JSON document, the
// bytes of every buffer, and typed reads of accessors. Every error is an InputError naming the file
// and the glTF path ("scene.glb: accessors[3]: ...").
//
// Why not assimp here (it reads the meshes of every other format): Debian 12's assimp 5.2.5 glTF2
// importer keeps only the values of a CUBICSPLINE sampler (its tangents are dropped) and records
// no STEP/LINEAR mode, so the glTF's own poses could not be reproduced; and its errors cannot name
// the glTF path at fault. The reader is the part of the spec aoeval needs: buffers (GLB chunk,
// data: URI, file), bufferViews, non-sparse accessors.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace aoeval {

class GltfDocument {
 public:
  // Reads `path` (.glb or .gltf) and every buffer it names; InputError on any problem.
  explicit GltfDocument(const std::string& path);

  const nlohmann::json& json() const { return json_; }
  const std::string& file() const { return file_; }

  // The array `key` of the document (empty when absent).
  const nlohmann::json& array(const char* key) const;

  // Accessor `index` read by `where` (the glTF path that refers to it, for messages). Each element
  // has `components` floats (SCALAR 1, VEC3 3, VEC4 4, MAT4 16), which must match `type`;
  // normalized integer components are converted as the spec says. NaN and infinities are errors.
  std::vector<float> floats(const nlohmann::json& index, const std::string& type,
                            const std::string& where) const;
  // An index accessor (unsigned byte, short or int, SCALAR).
  std::vector<uint32_t> indices(const nlohmann::json& index, const std::string& where) const;
  // The element count of accessor `index`.
  size_t count(const nlohmann::json& index, const std::string& where) const;

  // InputError "file: where: message".
  [[noreturn]] void fail(const std::string& where, const std::string& message) const;

 private:
  const nlohmann::json& accessor(const nlohmann::json& index, const std::string& where) const;
  std::string file_;
  nlohmann::json json_;
  std::vector<std::vector<uint8_t>> buffers_;
};

// An integer index into the document's array `key` (`value` at `where`), range-checked.
size_t gltf_index(const GltfDocument& doc, const nlohmann::json& value, const char* key,
                  const std::string& where);

}  // namespace aoeval
