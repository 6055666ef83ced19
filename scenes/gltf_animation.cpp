#include "scenes/gltf_animation.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <set>

namespace aoeval {

namespace {

std::vector<double> numbers(const GltfDocument& doc, const nlohmann::json& node, const char* key,
                            size_t n, const std::string& where) {
  const nlohmann::json& v = node[key];
  if (!v.is_array() || v.size() != n) doc.fail(where, "expected " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
      doc.fail(where,
               "element " + std::to_string(i) + " is not a finite number (" + v[i].dump() + ")");
    out.push_back(v[i].get<double>());
  }
  return out;
}

int optional_index(const GltfDocument& doc, const nlohmann::json& node, const char* key,
                   const char* array, const std::string& where) {
  if (!node.contains(key)) return -1;
  return static_cast<int>(gltf_index(doc, node[key], array, where + "." + key));
}

glm::dmat4 local_matrix(const GltfNode& n) {
  if (n.has_matrix) return n.matrix;
  return glm::translate(glm::dmat4(1.0), n.translation) * glm::mat4_cast(n.rotation) *
         glm::scale(glm::dmat4(1.0), n.scale);
}

glm::dquat quat(const double* v) {
  return glm::dquat(v[3], v[0], v[1], v[2]);
}

// Appendix C's slerp: along the shorter arc, linear when the keys (nearly) coincide.
glm::dquat slerp(glm::dquat a, glm::dquat b, double t) {
  double d = glm::dot(a, b);
  if (d < 0.0) {
    b = -b;
    d = -d;
  }
  if (d > 1.0 - 1e-12) return glm::normalize(a * (1.0 - t) + b * t);
  const double angle = std::acos(d), s = std::sin(angle);
  return a * (std::sin((1.0 - t) * angle) / s) + b * (std::sin(t * angle) / s);
}

}  // namespace

std::vector<GltfNode> read_gltf_nodes(const GltfDocument& doc) {
  const nlohmann::json& items = doc.array("nodes");
  std::vector<GltfNode> nodes(items.size());
  std::set<std::string> used;
  for (size_t i = 0; i < items.size(); ++i) {
    const std::string where = "nodes[" + std::to_string(i) + "]";
    const nlohmann::json& j = items[i];
    if (!j.is_object()) doc.fail(where, "expected an object");
    GltfNode& n = nodes[i];
    std::string name =
        j.contains("name") && j["name"].is_string() ? j["name"].get<std::string>() : "";
    if (name.empty()) name = where;
    if (used.count(name)) {  // appended in two steps: GCC 12's -Wrestrict misfires on "." + string
      name += '.';
      name += std::to_string(i);
    }
    used.insert(name);
    n.name = name;
    n.mesh = optional_index(doc, j, "mesh", "meshes", where);
    n.camera = optional_index(doc, j, "camera", "cameras", where);
    if (j.contains("matrix")) {
      const std::vector<double> m = numbers(doc, j, "matrix", 16, where + ".matrix");
      n.matrix = glm::make_mat4(m.data());  // column-major, as glTF stores it
      n.has_matrix = true;
    }
    if (j.contains("translation")) {
      const auto t = numbers(doc, j, "translation", 3, where + ".translation");
      n.translation = {t[0], t[1], t[2]};
    }
    if (j.contains("scale")) {
      const auto s = numbers(doc, j, "scale", 3, where + ".scale");
      n.scale = {s[0], s[1], s[2]};
    }
    if (j.contains("rotation")) {
      const auto r = numbers(doc, j, "rotation", 4, where + ".rotation");
      n.rotation = quat(r.data());
      if (std::abs(glm::length(n.rotation) - 1.0) > 1e-3)
        doc.fail(where + ".rotation", "not a unit quaternion");
      n.rotation = glm::normalize(n.rotation);
    }
  }
  for (size_t i = 0; i < items.size(); ++i) {
    if (!items[i].contains("children")) continue;
    const std::string where = "nodes[" + std::to_string(i) + "].children";
    if (!items[i]["children"].is_array()) doc.fail(where, "expected an array");
    size_t c = 0;
    for (const auto& child : items[i]["children"]) {
      const size_t k = gltf_index(doc, child, "nodes", where + "[" + std::to_string(c++) + "]");
      if (nodes[k].parent >= 0 || k == i)
        doc.fail(where, "nodes[" + std::to_string(k) + "] has more than one parent");
      nodes[k].parent = static_cast<int>(i);
    }
  }
  for (size_t i = 0; i < nodes.size(); ++i) {  // a cycle never reaches a root
    int p = nodes[i].parent;
    for (size_t steps = 0; p >= 0; ++steps, p = nodes[static_cast<size_t>(p)].parent)
      if (steps > nodes.size())
        doc.fail("nodes[" + std::to_string(i) + "]", "its parents form a cycle");
  }
  return nodes;
}

std::vector<GltfAnimation> read_gltf_animations(const GltfDocument& doc,
                                                const std::vector<GltfNode>& nodes) {
  std::vector<GltfAnimation> out;
  const nlohmann::json& items = doc.array("animations");
  for (size_t a = 0; a < items.size(); ++a) {
    const std::string at = "animations[" + std::to_string(a) + "]";
    const nlohmann::json& j = items[a];
    if (!j.is_object() || !j.contains("channels") || !j["channels"].is_array() ||
        !j.contains("samplers") || !j["samplers"].is_array())
      doc.fail(at, "an animation needs channels and samplers");
    GltfAnimation anim;
    anim.name = j.contains("name") && j["name"].is_string() && !j["name"].get<std::string>().empty()
                    ? j["name"].get<std::string>()
                    : at;
    anim.start = 1e300;
    anim.end = -1e300;
    const nlohmann::json& samplers = j["samplers"];
    if (j["channels"].empty()) doc.fail(at + ".channels", "an animation needs a channel");
    for (size_t c = 0; c < j["channels"].size(); ++c) {
      const std::string cat = at + ".channels[" + std::to_string(c) + "]";
      const nlohmann::json& ch = j["channels"][c];
      if (!ch.is_object() || !ch.contains("target") || !ch["target"].is_object() ||
          !ch.contains("sampler"))
        doc.fail(cat, "a channel needs a sampler and a target");
      const nlohmann::json& target = ch["target"];
      if (!target.contains("node")) doc.fail(cat + ".target", "a channel needs a target node");
      GltfChannel channel;
      channel.node = gltf_index(doc, target["node"], "nodes", cat + ".target.node");
      const std::string path = target.value("path", "");
      if (path == "weights")
        doc.fail(cat + ".target.path", "morph target weights are not supported");
      if (path != "translation" && path != "rotation" && path != "scale")
        doc.fail(cat + ".target.path", "unknown path '" + path + "'");
      channel.path = path == "translation" ? GltfPath::translation
                     : path == "rotation"  ? GltfPath::rotation
                                           : GltfPath::scale;
      if (nodes[channel.node].has_matrix)
        doc.fail(cat, "animates node '" + nodes[channel.node].name +
                          "', which has a matrix (the spec allows TRS targets only)");
      if (!ch["sampler"].is_number_unsigned() || ch["sampler"].get<size_t>() >= samplers.size())
        doc.fail(cat + ".sampler", "expected an index into " + at + ".samplers");
      const size_t s = ch["sampler"].get<size_t>();
      const std::string sat = at + ".samplers[" + std::to_string(s) + "]";
      const nlohmann::json& sampler = samplers[s];
      if (!sampler.is_object() || !sampler.contains("input") || !sampler.contains("output"))
        doc.fail(sat, "a sampler needs input and output");
      const std::string mode = sampler.value("interpolation", "LINEAR");
      if (mode != "LINEAR" && mode != "STEP" && mode != "CUBICSPLINE")
        doc.fail(sat + ".interpolation", "unknown interpolation '" + mode + "'");
      channel.interpolation = mode == "STEP"          ? GltfInterpolation::step
                              : mode == "CUBICSPLINE" ? GltfInterpolation::cubic
                                                      : GltfInterpolation::linear;
      const std::vector<float> times = doc.floats(sampler["input"], "SCALAR", sat + ".input");
      if (times.empty()) doc.fail(cat, "its sampler has no keys (" + sat + ".input is empty)");
      for (size_t k = 1; k < times.size(); ++k)
        if (!(times[k] > times[k - 1]))
          doc.fail(sat + ".input", "key times must increase (key " + std::to_string(k) + ")");
      const size_t n = channel.path == GltfPath::rotation ? 4 : 3;
      const std::vector<float> values =
          doc.floats(sampler["output"], n == 4 ? "VEC4" : "VEC3", sat + ".output");
      const size_t per_key = channel.interpolation == GltfInterpolation::cubic ? 3 * n : n;
      if (values.size() != times.size() * per_key)
        doc.fail(sat + ".output", std::to_string(values.size() / n) + " values for " +
                                      std::to_string(times.size()) + " keys (" + mode + ")");
      channel.times.assign(times.begin(), times.end());
      channel.values.assign(values.begin(), values.end());
      anim.start = std::min(anim.start, channel.times.front());
      anim.end = std::max(anim.end, channel.times.back());
      anim.channels.push_back(std::move(channel));
    }
    out.push_back(std::move(anim));
  }
  return out;
}

std::vector<double> sample_channel(const GltfChannel& c, double t) {
  const size_t n = c.path == GltfPath::rotation ? 4 : 3;
  const bool cubic = c.interpolation == GltfInterpolation::cubic;
  const size_t per_key = cubic ? 3 * n : n;
  // The value of key k (the middle of a cubic triplet).
  auto value = [&](size_t k) { return c.values.data() + k * per_key + (cubic ? n : 0); };
  const size_t keys = c.times.size();
  if (t <= c.times.front() || keys == 1) return {value(0), value(0) + n};
  if (t >= c.times.back()) return {value(keys - 1), value(keys - 1) + n};
  const size_t k =
      static_cast<size_t>(std::upper_bound(c.times.begin(), c.times.end(), t) - c.times.begin()) -
      1;
  if (c.interpolation == GltfInterpolation::step) return {value(k), value(k) + n};
  const double td = c.times[k + 1] - c.times[k], u = (t - c.times[k]) / td;
  std::vector<double> out(n);
  if (cubic) {
    const double* b = c.values.data() + k * per_key + 2 * n;  // out-tangent of key k
    const double* a = c.values.data() + (k + 1) * per_key;    // in-tangent of key k + 1
    const double u2 = u * u, u3 = u2 * u;
    for (size_t i = 0; i < n; ++i)
      out[i] = (2 * u3 - 3 * u2 + 1) * value(k)[i] + td * (u3 - 2 * u2 + u) * b[i] +
               (-2 * u3 + 3 * u2) * value(k + 1)[i] + td * (u3 - u2) * a[i];
    if (n == 4) {
      const glm::dquat q = glm::normalize(quat(out.data()));
      out = {q.x, q.y, q.z, q.w};
    }
    return out;
  }
  if (n == 4) {
    const glm::dquat q = slerp(quat(value(k)), quat(value(k + 1)), u);
    return {q.x, q.y, q.z, q.w};
  }
  for (size_t i = 0; i < n; ++i) out[i] = value(k)[i] + u * (value(k + 1)[i] - value(k)[i]);
  return out;
}

std::vector<GltfNode> posed_nodes(const std::vector<GltfNode>& nodes,
                                  const GltfAnimation* animation, double t) {
  std::vector<GltfNode> out = nodes;
  if (!animation) return out;
  for (const GltfChannel& c : animation->channels) {
    const std::vector<double> v = sample_channel(c, t);
    GltfNode& n = out[c.node];
    if (c.path == GltfPath::translation) n.translation = {v[0], v[1], v[2]};
    if (c.path == GltfPath::scale) n.scale = {v[0], v[1], v[2]};
    if (c.path == GltfPath::rotation) n.rotation = glm::normalize(quat(v.data()));
  }
  return out;
}

std::vector<glm::dmat4> world_matrices(const std::vector<GltfNode>& nodes) {
  std::vector<glm::dmat4> world(nodes.size());
  std::vector<bool> done(nodes.size(), false);
  std::function<const glm::dmat4&(size_t)> get = [&](size_t i) -> const glm::dmat4& {
    if (!done[i]) {
      const glm::dmat4 local = local_matrix(nodes[i]);
      world[i] = nodes[i].parent < 0 ? local : get(static_cast<size_t>(nodes[i].parent)) * local;
      done[i] = true;
    }
    return world[i];
  };
  for (size_t i = 0; i < nodes.size(); ++i) get(i);
  return world;
}

}  // namespace aoeval
