#include "scenes/gltf_document.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/json_reader.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> read_bytes(const fs::path& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  if (!ok) return {};
  std::ostringstream s;
  s << in.rdbuf();
  const std::string text = s.str();
  return {text.begin(), text.end()};
}

uint32_t le32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 |
         uint32_t(b[at + 3]) << 24;
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+' || c == '-') return 62;
  if (c == '/' || c == '_') return 63;
  return -1;
}

bool decode_base64(const std::string& text, std::vector<uint8_t>& out) {
  uint32_t acc = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const int v = base64_value(c);
    if (v < 0) return false;
    acc = (acc << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<uint8_t>(acc >> bits));
    }
  }
  return true;
}

// Percent-decoding of a relative URI ("my%20file.bin").
std::string uri_path(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size()) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

int components_of(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT4") return 16;
  return 0;
}

int component_bytes(int component_type) {
  switch (component_type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
  }
  return 0;
}

}  // namespace

void GltfDocument::fail(const std::string& where, const std::string& message) const {
  throw InputError(file_ + ": " + where + ": " + message);
}

size_t gltf_index(const GltfDocument& doc, const nlohmann::json& value, const char* key,
                  const std::string& where) {
  const nlohmann::json& items = doc.array(key);
  if (!value.is_number_unsigned() || value.get<uint64_t>() >= items.size())
    doc.fail(where, "expected an index into " + std::string(key) + " (0.." +
                        std::to_string(items.size()) + "), got " + value.dump());
  return value.get<size_t>();
}

GltfDocument::GltfDocument(const std::string& path) : file_(path) {
  bool ok = false;
  const std::vector<uint8_t> bytes = read_bytes(path, ok);
  if (!ok) throw InputError(path + ": cannot open glTF file");
  std::vector<uint8_t> bin;
  bool has_bin = false;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    if (bytes.size() < 20 || le32(bytes, 4) != 2)
      throw InputError(path + ": not a GLB 2 file (header)");
    const size_t length = std::min<size_t>(le32(bytes, 8), bytes.size());
    size_t at = 12;
    bool has_json = false;
    while (at + 8 <= length) {
      const size_t chunk = le32(bytes, at), type = le32(bytes, at + 4);
      if (at + 8 + chunk > length)
        throw InputError(path + ": GLB chunk at byte " + std::to_string(at) +
                         " runs past the end of the file");
      const auto* data = bytes.data() + at + 8;
      if (type == 0x4E4F534Au && !has_json) {
        json_ = parse_json_text(std::string(data, data + chunk), path);
        has_json = true;
      } else if (type == 0x004E4942u && !has_bin) {
        bin.assign(data, data + chunk);
        has_bin = true;
      }
      at += 8 + chunk;
    }
    if (!has_json) throw InputError(path + ": GLB file without a JSON chunk");
  } else {
    json_ = parse_json_file(path);
  }
  if (!json_.is_object()) throw InputError(path + ": a glTF document must be a JSON object");
  const nlohmann::json& asset = json_.value("asset", nlohmann::json::object());
  const std::string version = asset.is_object() ? asset.value("version", "") : "";
  if (version.rfind("2.", 0) != 0)
    fail("asset.version", "aoeval reads glTF 2.x, the file says '" + version + "'");
  const nlohmann::json& buffers = array("buffers");
  for (size_t i = 0; i < buffers.size(); ++i) {
    const std::string where = "buffers[" + std::to_string(i) + "]";
    const nlohmann::json& b = buffers[i];
    if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
      fail(where, "a buffer needs a byteLength");
    const size_t length = b["byteLength"].get<size_t>();
    std::vector<uint8_t> data;
    if (!b.contains("uri")) {
      if (i != 0 || !has_bin) fail(where, "no uri, and the file has no GLB binary chunk for it");
      data = bin;
    } else {
      const std::string uri = b["uri"].is_string() ? b["uri"].get<std::string>() : "";
      if (uri.rfind("data:", 0) == 0) {
        const size_t comma = uri.find(";base64,");
        if (comma == std::string::npos || !decode_base64(uri.substr(comma + 8), data))
          fail(where + ".uri", "a data: URI must hold base64 data");
      } else {
        const fs::path file = fs::path(path).parent_path() / uri_path(uri);
        data = read_bytes(file, ok);
        if (!ok) fail(where + ".uri", "buffer file '" + file.string() + "' not found");
      }
    }
    if (data.size() < length)
      fail(where, "holds " + std::to_string(data.size()) + " bytes, its byteLength says " +
                      std::to_string(length));
    data.resize(length);
    buffers_.push_back(std::move(data));
  }
}

const nlohmann::json& GltfDocument::array(const char* key) const {
  static const nlohmann::json empty = nlohmann::json::array();
  if (!json_.contains(key)) return empty;
  const nlohmann::json& a = json_[key];
  if (!a.is_array()) fail(key, "expected an array");
  return a;
}

const nlohmann::json& GltfDocument::accessor(const nlohmann::json& index,
                                             const std::string& where) const {
  return array("accessors")[gltf_index(*this, index, "accessors", where)];
}

size_t GltfDocument::count(const nlohmann::json& index, const std::string& where) const {
  const nlohmann::json& a = accessor(index, where);
  if (!a.is_object() || !a.contains("count") || !a["count"].is_number_unsigned())
    fail("accessors[" + index.dump() + "]", "an accessor needs a count");
  return a["count"].get<size_t>();
}

namespace {

// The bytes an accessor reads: base pointer and stride, every element checked to lie in its
// bufferView and buffer. `data` is null for an accessor without a bufferView (all zeros).
struct AccessorBytes {
  const uint8_t* data = nullptr;
  size_t stride = 0, count = 0;
  int component_type = 0, components = 0;
  bool normalized = false;
};

AccessorBytes accessor_bytes(const GltfDocument& doc, const nlohmann::json& a,
                             const std::string& at,
                             const std::vector<std::vector<uint8_t>>& buffers) {
  AccessorBytes r;
  if (!a.is_object()) doc.fail(at, "expected an object");
  if (a.contains("sparse")) doc.fail(at + ".sparse", "sparse accessors are not supported");
  r.count = a.value("count", size_t(0));
  r.component_type = a.value("componentType", 0);
  r.components = components_of(a.value("type", ""));
  r.normalized = a.value("normalized", false);
  const int size = component_bytes(r.component_type);
  if (size == 0) doc.fail(at + ".componentType", "unknown component type");
  if (r.components == 0) doc.fail(at + ".type", "unknown or unsupported type");
  const size_t element = static_cast<size_t>(size * r.components);
  r.stride = element;
  if (!a.contains("bufferView")) return r;
  const size_t v = gltf_index(doc, a["bufferView"], "bufferViews", at + ".bufferView");
  const nlohmann::json& view = doc.array("bufferViews")[v];
  const std::string vat = "bufferViews[" + std::to_string(v) + "]";
  if (!view.is_object() || !view.contains("buffer")) doc.fail(vat, "a bufferView needs a buffer");
  const size_t b = gltf_index(doc, view["buffer"], "buffers", vat + ".buffer");
  const size_t view_offset = view.value("byteOffset", size_t(0));
  const size_t view_length = view.value("byteLength", size_t(0));
  if (view_offset + view_length > buffers[b].size())
    doc.fail(vat, "runs past the end of buffers[" + std::to_string(b) + "] (" +
                      std::to_string(buffers[b].size()) + " bytes)");
  r.stride = view.value("byteStride", element);
  if (r.stride < element) doc.fail(vat + ".byteStride", "smaller than one element");
  const size_t offset = a.value("byteOffset", size_t(0));
  if (r.count > 0 && offset + r.stride * (r.count - 1) + element > view_length)
    doc.fail(at, std::to_string(r.count) + " elements run past the end of " + vat);
  r.data = buffers[b].data() + view_offset + offset;
  return r;
}

float component(const AccessorBytes& r, size_t i, int c) {
  if (!r.data) return 0.0f;
  const uint8_t* p = r.data + i * r.stride + c * component_bytes(r.component_type);
  switch (r.component_type) {
    case 5126: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case 5120: {
      const auto v = static_cast<int8_t>(*p);
      return r.normalized ? std::max(v / 127.0f, -1.0f) : static_cast<float>(v);
    }
    case 5121:
      return r.normalized ? *p / 255.0f : static_cast<float>(*p);
    case 5122: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return r.normalized ? std::max(v / 32767.0f, -1.0f) : static_cast<float>(v);
    }
    case 5123: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return r.normalized ? v / 65535.0f : static_cast<float>(v);
    }
  }
  uint32_t v;
  std::memcpy(&v, p, 4);
  return static_cast<float>(v);
}

}  // namespace

std::vector<float> GltfDocument::floats(const nlohmann::json& index, const std::string& type,
                                        const std::string& where) const {
  const nlohmann::json& a = accessor(index, where);
  const std::string at = "accessors[" + index.dump() + "]";
  const AccessorBytes r = accessor_bytes(*this, a, at, buffers_);
  if (a.value("type", "") != type)
    fail(where, at + " is " + a.value("type", "?") + ", expected " + type);
  if (r.component_type != 5126 && !r.normalized)
    fail(where, at + " must hold floats (or normalized integers)");
  std::vector<float> out(r.count * static_cast<size_t>(r.components));
  for (size_t i = 0; i < r.count; ++i)
    for (int c = 0; c < r.components; ++c) {
      const float v = component(r, i, c);
      if (!std::isfinite(v))
        fail(where,
             at + " element " + std::to_string(i) + " is " + (std::isnan(v) ? "NaN" : "inf"));
      out[i * r.components + c] = v;
    }
  return out;
}

std::vector<uint32_t> GltfDocument::indices(const nlohmann::json& index,
                                            const std::string& where) const {
  const nlohmann::json& a = accessor(index, where);
  const std::string at = "accessors[" + index.dump() + "]";
  const AccessorBytes r = accessor_bytes(*this, a, at, buffers_);
  if (r.components != 1 || r.normalized ||
      (r.component_type != 5121 && r.component_type != 5123 && r.component_type != 5125))
    fail(where, at + " must be SCALAR unsigned byte, short or int indices");
  std::vector<uint32_t> out(r.count);
  for (size_t i = 0; i < r.count; ++i) {
    if (!r.data) continue;
    const uint8_t* p = r.data + i * r.stride;
    if (r.component_type == 5121) {
      out[i] = *p;
    } else if (r.component_type == 5123) {
      uint16_t v;
      std::memcpy(&v, p, 2);
      out[i] = v;
    } else {
      std::memcpy(&out[i], p, 4);
    }
  }
  return out;
}

}  // namespace aoeval
