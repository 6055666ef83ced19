#include "estimators/vertex_baked/vertex_bake.h"

#include "scenes/instances.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <string>
#include <unordered_map>

#include "base/errors.h"
#include "sampling/ray_offset.h"
#include "scenes/random.h"

namespace aoeval {

namespace {

// One triangle's bake: its area (the vertex-averaging weight) and, per side, accessibility and the
// mean unoccluded direction of Listing 17-1.
struct TriangleBake {
  float area = 0.0f;
  float accessibility[2] = {1.0f, 1.0f};
  glm::vec3 bent[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};
};

TriangleBake bake_triangle(RTCScene scene, RTCIntersectContext& context, const BakeSettings& s,
                           const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                           uint64_t stream, float extent, std::vector<glm::vec2>& square,
                           uint64_t& traced) {
  TriangleBake b;
  const glm::vec3 c = glm::cross(p1 - p0, p2 - p0);
  const float len = glm::length(c);
  // A degenerate triangle has no hemisphere; its zero area keeps it out of every vertex average.
  if (!(len > 0.0f) || !std::isfinite(len)) return b;
  b.area = 0.5f * len;
  const glm::vec3 n = c / len;
  const glm::vec3 centre = (p0 + p1 + p2) / 3.0f;  // §17.2: "computed these values at the center"
  const float offset = origin_offset(centre, extent);
  const auto m = static_cast<uint32_t>(s.rays);
  for (int side = 0; side < 2; ++side) {
    const glm::vec3 ns = side == 0 ? n : -n;
    const Frame frame = make_frame(ns);
    const glm::vec3 o = centre + ns * offset;
    sample_square(s.sampler, s.seed, mix_seed(stream, static_cast<uint64_t>(side)), 0, m,
                  square.data());
    uint32_t open = 0;
    glm::vec3 sum(0.0f);
    for (uint32_t i = 0; i < m; ++i) {
      // Uniform directions over the hemisphere, the distribution of Listing 17-2's rejection
      // sampling, through the inverse map so that stratified point sets stay stratified.
      const glm::vec3 w = frame.to_world(square_to_uniform_hemisphere(square[i]));
      RTCRay ray{};
      ray.org_x = o.x, ray.org_y = o.y, ray.org_z = o.z;
      ray.dir_x = w.x, ray.dir_y = w.y, ray.dir_z = w.z;
      ray.tnear = 0.0f;
      ray.tfar = std::numeric_limits<float>::infinity();
      ray.mask = 0xFFFFFFFFu;
      rtcOccluded1(scene, &context, &ray);
      if (ray.tfar >= 0.0f) {  // Embree sets tfar = -inf on a hit
        ++open;
        sum += w;  // Listing 17-1: avgUnoccluded += ray.direction
      }
    }
    traced += m;
    b.accessibility[side] =
        static_cast<float>(open) / static_cast<float>(m);  // numUnoccluded/numRays
    b.bent[side] = sum / static_cast<float>(m);
  }
  return b;
}

}  // namespace

void check_subdivide(const Scene& scene, int levels) {
  if (levels < 0) throw InputError("subdivide: must be at least 0");
  const uint64_t base = scene.triangle_count();
  uint64_t total = base;
  for (int l = 0; l < levels && total <= kMaxBakedTriangles; ++l) total *= 4;
  if (total > kMaxBakedTriangles)
    throw InputError("subdivide=" + std::to_string(levels) + ": " + std::to_string(base) +
                     " triangles become more than " + std::to_string(kMaxBakedTriangles) +
                     " after subdivision (the bake's memory limit); use fewer levels");
}

TriangleMesh subdivide_mesh(const TriangleMesh& mesh, int levels) {
  TriangleMesh m;
  m.positions = mesh.positions;
  m.triangles = mesh.triangles;
  for (int level = 0; level < levels; ++level) {
    // One midpoint per undirected edge, so neighbours share it and the vertex average spans them.
    std::unordered_map<uint64_t, uint32_t> midpoints;
    midpoints.reserve(m.triangles.size() * 2);
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, inserted] =
          midpoints.try_emplace(key, static_cast<uint32_t>(m.positions.size()));
      if (inserted) {
        const glm::vec3 p = 0.5f * (m.positions[a] + m.positions[b]);  // symmetric in a, b
        m.positions.push_back(p);
      }
      return it->second;
    };
    std::vector<glm::uvec3> next;
    next.reserve(m.triangles.size() * 4);
    for (const glm::uvec3& t : m.triangles) {
      const uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
      // The four children keep the parent's winding; lookup()'s descent relies on this order.
      next.emplace_back(t.x, ab, ca);  // 0: corner p0
      next.emplace_back(ab, t.y, bc);  // 1: corner p1
      next.emplace_back(ca, bc, t.z);  // 2: corner p2
      next.emplace_back(bc, ca, ab);   // 3: the middle, upside down
    }
    m.triangles.swap(next);
  }
  return m;
}

VertexBake bake_vertices(const Scene& scene, const EmbreeScene& embree, const BakeSettings& s) {
  if (s.rays < 1) throw InputError("rays: must be at least 1");
  // Per-vertex AO belongs to each placed copy's vertices (an instance's neighbours differ), so a
  // bake of the prototype would be wrong for every instance; instanced scenes are refused.
  refuse_instances(scene, "per-vertex baking (vertex-baked, shadowmap-ao per-vertex)");
  check_subdivide(scene, s.subdivide);
  const glm::vec3 e = scene.bounds().extent();
  const float extent = std::max({e.x, e.y, e.z});
  VertexBake bake;
  bake.subdivide = s.subdivide;
  bake.objects.resize(scene.objects.size());
  std::atomic<uint64_t> traced{0};
  for (size_t geom = 0; geom < scene.objects.size(); ++geom) {
    TriangleMesh sub = subdivide_mesh(scene.objects[geom].mesh, s.subdivide);
    BakedMesh& bm = bake.objects[geom];
    bm.positions = std::move(sub.positions);
    bm.triangles = std::move(sub.triangles);
    std::vector<TriangleBake> tris(bm.triangles.size());
    parallel_for_embree(
        tbb::blocked_range<size_t>(0, tris.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
          RTCIntersectContext context;
          rtcInitIntersectContext(&context);
          std::vector<glm::vec2> square(static_cast<size_t>(s.rays));
          uint64_t local = 0;
          for (size_t t = r.begin(); t < r.end(); ++t) {
            const glm::uvec3 tri = bm.triangles[t];
            tris[t] =
                bake_triangle(embree.handle(), context, s, bm.positions[tri.x], bm.positions[tri.y],
                              bm.positions[tri.z], mix_seed(geom, t), extent, square, local);
          }
          traced += local;
        });
    // §17.2: "stored values at each vertex that held the average of the values from the adjacent
    // faces", here weighted by area so that slivers count as little as they cover. Summed in
    // triangle order: same bits whatever the thread count.
    const size_t nv = bm.positions.size();
    std::vector<double> weight(nv, 0.0);
    std::vector<double> acc[2] = {std::vector<double>(nv, 0.0), std::vector<double>(nv, 0.0)};
    std::vector<glm::dvec3> bent[2] = {std::vector<glm::dvec3>(nv, glm::dvec3(0.0)),
                                       std::vector<glm::dvec3>(nv, glm::dvec3(0.0))};
    for (size_t t = 0; t < tris.size(); ++t) {
      const TriangleBake& b = tris[t];
      const double w = b.area;
      for (int corner = 0; corner < 3; ++corner) {
        const uint32_t v = bm.triangles[t][corner];
        weight[v] += w;
        for (int side = 0; side < 2; ++side) {
          acc[side][v] += w * b.accessibility[side];
          bent[side][v] += w * glm::dvec3(b.bent[side]);
        }
      }
    }
    for (int side = 0; side < 2; ++side) {
      bm.accessibility[side].resize(nv);
      bm.bent[side].resize(nv);
      for (size_t v = 0; v < nv; ++v) {
        // A vertex of degenerate triangles only (never interpolated with weight) is left open.
        const bool any = weight[v] > 0.0;
        bm.accessibility[side][v] = any ? static_cast<float>(acc[side][v] / weight[v]) : 1.0f;
        bm.bent[side][v] = any ? glm::vec3(bent[side][v] / weight[v]) : glm::vec3(0.0f);
      }
    }
  }
  bake.rays_traced = traced;
  return bake;
}

BakedSample lookup(const VertexBake& bake, unsigned geom, unsigned prim, float u, float v,
                   int side) {
  const BakedMesh& m = bake.objects[geom];
  // Descend from the original triangle to the sub-triangle holding (u, v), rewriting (u, v) in the
  // child's own barycentrics at each level (children as in subdivide_mesh).
  size_t t = prim;
  for (int level = 0; level < bake.subdivide; ++level) {
    size_t child;
    if (u >= 0.5f) {
      child = 1, u = 2.0f * u - 1.0f, v = 2.0f * v;
    } else if (v >= 0.5f) {
      child = 2, u = 2.0f * u, v = 2.0f * v - 1.0f;
    } else if (u + v <= 0.5f) {
      child = 0, u = 2.0f * u, v = 2.0f * v;
    } else {
      child = 3, u = 1.0f - 2.0f * u, v = 1.0f - 2.0f * v;
    }
    t = 4 * t + child;
  }
  const glm::uvec3 tri = m.triangles[t];
  const float w = 1.0f - u - v;
  const auto& a = m.accessibility[side];
  const auto& b = m.bent[side];
  BakedSample out;
  // §17.4: the per-vertex values "interpolated at each pixel" (Gouraud interpolation).
  out.accessibility = std::clamp(w * a[tri.x] + u * a[tri.y] + v * a[tri.z], 0.0f, 1.0f);
  const glm::vec3 bn = w * b[tri.x] + u * b[tri.y] + v * b[tri.z];
  const float len = glm::length(bn);
  out.bent = len > 0.0f ? bn / len : glm::vec3(0.0f);
  return out;
}

}  // namespace aoeval
