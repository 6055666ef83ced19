#include "scenes/mesh_io.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/input_limits.h"
#include "scenes/q3_bsp.h"

namespace aoeval {

namespace {

// Whitespace tokenizer over an OFF file that skips '#' comments and tracks line numbers.
class OffTokens {
 public:
  OffTokens(std::string text, std::string path) : text_(std::move(text)), path_(std::move(path)) {}

  bool next(std::string_view& token) {
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        if (c == '\n') ++line_;
        ++pos_;
      } else {
        break;
      }
    }
    if (pos_ >= text_.size()) return false;
    size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) &&
           text_[pos_] != '#')
      ++pos_;
    token = std::string_view(text_).substr(start, pos_ - start);
    return true;
  }

  std::string_view require(const char* what) {
    std::string_view t;
    if (!next(t)) fail(std::string("unexpected end of file, expected ") + what);
    return t;
  }

  double number(const char* what) {
    std::string_view t = require(what);
    std::string s(t);
    char* end = nullptr;
    double v = std::strtod(s.c_str(), &end);  // accepts "nan"/"inf": validate_mesh reports them
    if (end != s.c_str() + s.size()) fail(std::string("expected ") + what + ", got '" + s + "'");
    return v;
  }

  long long integer(const char* what) {
    std::string_view t = require(what);
    std::string s(t);
    char* end = nullptr;
    long long v = std::strtoll(s.c_str(), &end, 10);
    if (end != s.c_str() + s.size()) fail(std::string("expected ") + what + ", got '" + s + "'");
    return v;
  }

  // Bytes not yet read: a header's counts are checked against them before anything is allocated.
  size_t remaining() const { return text_.size() - pos_; }

  // Skips the rest of the current line (OFF faces may carry colours).
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(path_ + ":" + std::to_string(line_) + ": " + message);
  }

 private:
  std::string text_;
  std::string path_;
  size_t pos_ = 0;
  size_t line_ = 1;
};

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open mesh file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TriangleMesh load_off(const std::string& path) {
  OffTokens tok(read_file(path), path);
  std::string_view header = tok.require("OFF header");
  // "OFF" or "OFF<nv>" glued (rare) is not supported; COFF/NOFF carry extra per-vertex values.
  if (header != "OFF" && header != "COFF" && header != "NOFF" && header != "CNOFF")
    tok.fail("not an OFF file (header '" + std::string(header) + "')");
  const int extra_per_vertex = header == "COFF"    ? 4
                               : header == "NOFF"  ? 3
                               : header == "CNOFF" ? 7
                                                   : 0;
  long long nv = tok.integer("vertex count");
  long long nf = tok.integer("face count");
  tok.integer("edge count");
  if (nv <= 0 || nf <= 0 || nv > (1ll << 31) || nf > (1ll << 31))
    tok.fail("bad vertex/face counts " + std::to_string(nv) + " " + std::to_string(nf));
  // Every vertex takes at least (3 + extra) numbers of two bytes ("0 "), every face at least
  // "3 0 1 2\n": a header claiming more than the file can hold is rejected before the (possibly
  // many-gigabyte) allocation it asks for.
  const auto min_bytes = static_cast<unsigned long long>(nv) * 2ull * (3ull + extra_per_vertex) +
                         static_cast<unsigned long long>(nf) * 8ull;
  if (min_bytes > tok.remaining() + 1)
    tok.fail("header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
             " faces, more than the file's " + std::to_string(tok.remaining()) +
             " remaining bytes can hold");
  TriangleMesh mesh;
  mesh.positions.resize(static_cast<size_t>(nv));
  std::vector<glm::vec3> file_normals;
  auto coordinate = [&tok](const char* what) {
    const double v = tok.number(what);
    // NaN and inf pass here and validate_mesh names them; a finite value beyond float would be
    // undefined behaviour to cast, so it is reported here.
    if (std::isfinite(v) && !fits_float(v))
      tok.fail(std::string(what) + " " + std::to_string(v) + " does not fit a 32-bit float");
    return static_cast<float>(v);
  };
  for (auto& p : mesh.positions) {
    p.x = coordinate("x coordinate");
    p.y = coordinate("y coordinate");
    p.z = coordinate("z coordinate");
    for (int k = 0; k < extra_per_vertex; ++k) tok.number("vertex attribute");
  }
  mesh.triangles.reserve(static_cast<size_t>(nf));
  for (long long f = 0; f < nf; ++f) {
    long long n = tok.integer("face vertex count");
    if (n < 3 || n > 1000000)
      tok.fail("face " + std::to_string(f) + " has " + std::to_string(n) + " vertices");
    std::vector<uint32_t> idx(static_cast<size_t>(n));
    for (auto& i : idx) {
      long long v = tok.integer("vertex index");
      if (v < 0 || v >= nv)
        tok.fail("face " + std::to_string(f) + " indexes vertex " + std::to_string(v) + " of " +
                 std::to_string(nv));
      i = static_cast<uint32_t>(v);
    }
    tok.skip_line();  // optional face colour
    for (long long k = 1; k + 1 < n; ++k) mesh.triangles.emplace_back(idx[0], idx[k], idx[k + 1]);
  }
  validate_mesh(mesh, path);
  compute_vertex_normals(mesh);
  return mesh;
}

TriangleMesh load_mesh(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": mesh file not found");
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".off") return load_off(path);
  if (ext == ".bsp") return load_q3_bsp(path);  // assimp 5.2.5's Q3BSP importer fails (q3_bsp.h)

  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_PreTransformVertices | aiProcess_SortByPType |
                                  aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode) {
    throw InputError(path + ": assimp could not read it: " + importer.GetErrorString());
  }
  TriangleMesh mesh;
  bool all_have_normals = true;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    all_have_normals = all_have_normals && am->HasNormals();
  }
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;  // points and lines
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      mesh.positions.emplace_back(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
      if (all_have_normals) {
        glm::vec3 n(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z);
        float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        mesh.normals.push_back(std::isfinite(len) && len > 0 ? n / len : glm::vec3(0, 1, 0));
      }
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1],
                                  base + face.mIndices[2]);
    }
  }
  validate_mesh(mesh, path);
  if (!all_have_normals) compute_vertex_normals(mesh);
  return mesh;
}

}  // namespace aoeval
