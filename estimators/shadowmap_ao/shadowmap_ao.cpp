// shadowmap-ao: the Vulkan passes, the two receiver modes and the declaration (see shadowmap_ao.h).
#include "estimators/shadowmap_ao/shadowmap_ao.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "base/errors.h"
#include "estimators/seed_param.h"
#include "estimators/vertex_baked/vertex_bake.h"
#include "estimators/vulkan/raster_gbuffer.h"
#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_pipelines.h"
#include "scenes/instances.h"
#include "shadowmap_accumulate_comp_spv.h"
#include "shadowmap_depth_frag_spv.h"
#include "shadowmap_depth_vert_spv.h"

namespace aoeval {

namespace {

// The push-constant blocks of shadowmap_depth.vert and shadowmap_accumulate.comp (std430).
struct DepthPush {
  glm::vec4 centre_radius;
  uint32_t light;
};
struct AccumulatePush {
  glm::vec4 centre_radius;
  uint32_t first_light, light_count, resolution, receiver_count;
  uint32_t width, cosine, dome, pad;
  float bias, slope_bias, max_tan, pad2;
};
static_assert(sizeof(AccumulatePush) == 64);

constexpr uint32_t kGroup = 64;         // shadowmap_accumulate.comp's local_size_x
constexpr uint32_t kMaxGroups = 65535;  // the least maxComputeWorkGroupCount Vulkan guarantees

// The accumulators of one receiver side: (sum of lit · l, sum of w · lit) and the weight total.
struct SideSums {
  glm::vec4 lit;
  float total;
};

// Resolves one side's sums: AO = lit / total; the mean lit direction, normalised, as bent normal.
// A side no light was above (too few lights) was never tested and reads 1.
void resolve(const SideSums& s, float& ao, glm::vec3& bent) {
  ao = s.total > 0.0f ? std::clamp(s.lit.w / s.total, 0.0f, 1.0f) : 1.0f;
  const glm::vec3 b(s.lit);
  const float len = glm::length(b);
  bent = len > 0.0f ? b / len : glm::vec3(0.0f);
}

// The device side: the scene's triangles, the lights, the atlas of lights_per_pass shadow maps and
// the two pipelines. accumulate() runs every pass for a set of receivers and returns their sums.
class ShadowmapDevice {
 public:
  ShadowmapDevice(vk::Context& vk, const Scene& scene, const ShadowmapSettings& s)
      : vk_(vk), s_(s), timer_(vk, 2 * static_cast<uint32_t>(batches(s)) + 1) {
    refuse_instances(scene, "estimator 'shadowmap-ao' (shadow maps rasterise world-space copies)");
    const uint32_t atlas_width = static_cast<uint32_t>(s.resolution * s.lights_per_pass);
    if (atlas_width > vk.properties().limits.maxImageDimension2D)
      throw InputError("resolution x lights_per_pass: " + std::to_string(atlas_width) +
                       " texels exceed the device's largest image (" +
                       std::to_string(vk.properties().limits.maxImageDimension2D) + ")");
    const Bounds b = scene.bounds();
    if (b.empty()) throw InputError("scene: shadowmap-ao needs at least one triangle");
    // The maps cover the bounding sphere, 1 % wider so that no surface touches the clip planes.
    centre_radius_ = glm::vec4(b.center(), 0.505f * glm::length(b.extent()) + 1e-6f);
    std::vector<float> p;
    std::vector<uint32_t> idx;
    for (const SceneObject& o : scene.objects) {
      const auto base = static_cast<uint32_t>(p.size() / 3);
      for (const glm::vec3& v : o.mesh.positions) p.insert(p.end(), {v.x, v.y, v.z});
      for (const glm::uvec3& t : o.mesh.triangles)
        idx.insert(idx.end(), {base + t.x, base + t.y, base + t.z});
    }
    if (idx.empty()) throw InputError("scene: shadowmap-ao needs at least one triangle");
    vertex_count_ = static_cast<uint32_t>(idx.size());
    positions_ = vk::storage_buffer(vk, p);
    indices_ = vk::storage_buffer(vk, idx);
    // Each light's frame: d towards the light, u and v spanning its map; the maps fitted to the
    // sphere until the receivers are known (set_gbuffer, set_receivers).
    for (const glm::vec3& d : light_directions(s.lights, s.distribution, s.dome, s.seed)) {
      const glm::vec3 a = std::abs(d.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
      const glm::vec3 u = glm::normalize(glm::cross(a, d));
      basis_.push_back({u, glm::cross(d, u), d});
    }
    lights_ = vk::storage_buffer(vk, light_frames({}));

    vk::GraphicsDesc desc;
    desc.name = "shadowmap depth";
    desc.vertex = shadowmap_depth_vert_spv;
    desc.fragment = shadowmap_depth_frag_spv;
    desc.bindings = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                     VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};  // positions, lights, indices
    desc.push_constant_bytes = sizeof(DepthPush);
    desc.color_formats = {VK_FORMAT_R32_SFLOAT};
    desc.depth_compare = VK_COMPARE_OP_LESS;  // depth 0 is nearest the light
    depth_pipeline_ = std::make_unique<vk::GraphicsPipeline>(vk, desc);
    depth_set_ = depth_pipeline_->make_set({positions_, lights_, indices_});
    atlas_ = vk::Image2D(vk, static_cast<int>(atlas_width), s.resolution, VK_FORMAT_R32_SFLOAT,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
    atlas_depth_ =
        vk::Image2D(vk, static_cast<int>(atlas_width), s.resolution, VK_FORMAT_D32_SFLOAT);
    framebuffer_ = std::make_unique<vk::Framebuffer>(
        vk, *depth_pipeline_, std::vector<const vk::Image2D*>{&atlas_}, atlas_depth_);
    accumulate_ = std::make_unique<vk::ComputePipeline>(
        vk, "shadowmap accumulate", shadowmap_accumulate_comp_spv,
        std::vector<VkDescriptorType>{
            VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
            VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
        static_cast<uint32_t>(sizeof(AccumulatePush)),
        std::vector<vk::SpecConstant>{vk::spec_uint(0, s.mode == ShadowmapMode::vertex ? 1u : 0u)});
  }

  static int batches(const ShadowmapSettings& s) {
    return (s.lights + s.lights_per_pass - 1) / s.lights_per_pass;
  }

  // Mode pixel: receivers are the G-buffer's covered pixels (P, N, Ng read on the device).
  void set_gbuffer(const GBuffer& g) {
    std::vector<glm::vec3> points;
    for (size_t k = 0; k < g.pixel_count(); ++k)
      if (g.covered(k)) points.push_back(g.position[k]);
    lights_.upload(light_frames(points));
    gbuffer_ = vk::upload_gbuffer(vk_, g);
    width_ = static_cast<uint32_t>(g.width);
    receiver_count_ = static_cast<uint32_t>(g.pixel_count());
    receivers_ = vk::Buffer(vk_, 2 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    make_accumulators();
    set_ = accumulate_->make_set({atlas_, lights_, gbuffer_.position, gbuffer_.normal,
                                  gbuffer_.geometric_normal, receivers_, accumulators_});
  }

  // Mode vertex: receivers are points with face normals (position w = 1; 0 = skip).
  void set_receivers(const std::vector<glm::vec4>& position_normal) {
    std::vector<glm::vec3> points;
    for (size_t k = 0; k + 1 < position_normal.size(); k += 2)
      if (position_normal[k].w != 0.0f) points.push_back(glm::vec3(position_normal[k]));
    lights_.upload(light_frames(points));
    receiver_count_ = static_cast<uint32_t>(position_normal.size() / 2);
    width_ = 1;
    receivers_ = vk::Buffer(vk_, std::max<size_t>(1, position_normal.size()) * sizeof(glm::vec4),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!position_normal.empty()) receivers_.upload(position_normal);
    dummy_ = vk::Image2D(vk_, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT);
    make_accumulators();
    set_ =
        accumulate_->make_set({atlas_, lights_, dummy_, dummy_, dummy_, receivers_, accumulators_});
  }

  // Every pass: per batch, lights_per_pass shadow maps into the atlas ("shadow_maps"), then one
  // accumulation over all receivers ("accumulate"). Returns two SideSums per receiver.
  std::vector<SideSums> accumulate(std::map<std::string, double>& pass_ms) {
    const ShadowmapSettings& s = s_;
    const uint32_t res = static_cast<uint32_t>(s.resolution);
    vk_.submit([&](VkCommandBuffer cmd) {
      timer_.reset(cmd);
      vkCmdFillBuffer(cmd, accumulators_.handle(), 0, VK_WHOLE_SIZE, 0u);  // 0.0f bits
      vk::pass_barrier(cmd);
      for (int first = 0; first < s.lights; first += s.lights_per_pass) {
        const int count = std::min(s.lights_per_pass, s.lights - first);
        timer_.begin(cmd, "shadow_maps", vk::PassTimer::Work::draws);
        const VkClearColorValue far{{1.0f, 0.0f, 0.0f, 0.0f}};
        framebuffer_->begin(cmd, *depth_pipeline_, {far}, 1.0f);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, depth_pipeline_->layout(), 0,
                                1, &depth_set_, 0, nullptr);
        for (int k = 0; k < count; ++k) {
          // Light first + k draws into tile k: x in [k res, (k + 1) res).
          const VkViewport viewport{static_cast<float>(k * res), 0.0f, static_cast<float>(res),
                                    static_cast<float>(res),     0.0f, 1.0f};
          const VkRect2D scissor{{static_cast<int32_t>(k * res), 0}, {res, res}};
          vkCmdSetViewport(cmd, 0, 1, &viewport);
          vkCmdSetScissor(cmd, 0, 1, &scissor);
          const DepthPush push{centre_radius_, static_cast<uint32_t>(first + k)};
          depth_pipeline_->push(cmd, &push, sizeof(push));
          vkCmdDraw(cmd, vertex_count_, 1, 0, 0);
        }
        framebuffer_->end(cmd);
        vk::pass_barrier(cmd);
        timer_.end(cmd);
        timer_.begin(cmd, "accumulate", vk::PassTimer::Work::unflushed_dispatches);
        AccumulatePush push{};
        push.centre_radius = centre_radius_;
        push.first_light = static_cast<uint32_t>(first);
        push.light_count = static_cast<uint32_t>(count);
        push.resolution = res;
        push.receiver_count = receiver_count_;
        push.width = width_;
        push.cosine = s.weighting == Weighting::cosine ? 1u : 0u;
        push.dome = s.dome ? 1u : 0u;
        push.bias = s.bias;
        push.slope_bias = s.slope_bias;
        push.max_tan = kMaxBiasTan;
        const uint32_t groups = vk::group_count(receiver_count_, kGroup);
        const uint32_t columns = std::min(groups, kMaxGroups);
        accumulate_->dispatch(cmd, set_, push, columns, vk::group_count(groups, columns));
        vk::pass_barrier(cmd);
        timer_.end(cmd);
      }
    });
    pass_ms = timer_.read();
    const std::vector<glm::vec4> raw = accumulators_.download<glm::vec4>();
    std::vector<SideSums> sums(2 * static_cast<size_t>(receiver_count_));
    for (size_t k = 0; k < sums.size(); ++k) sums[k] = {raw[2 * k], raw[2 * k + 1].x};
    return sums;
  }

 private:
  // The lights' buffer (struct Light of shadowmap_common.glsl): u, v, (d, texel scale), fit. With
  // fit = receivers and receivers given, each map spans the receivers' extent along its u and v,
  // widened by two texels a side (and by 1e-6 R for the device's rounding of the same dot
  // products) so that every receiver falls inside; a receiver set narrower than 1e-3 R (one
  // probe point) gets that width. Depth keeps the sphere: every occluder between a receiver and
  // the light is drawn. Otherwise (fit = scene, or no receiver) the sphere, as before.
  std::vector<glm::vec4> light_frames(const std::vector<glm::vec3>& receivers) const {
    const glm::vec3 c(centre_radius_);
    const float radius = centre_radius_.w;
    const bool fit = s_.fit_receivers && !receivers.empty();
    std::vector<glm::vec4> out(4 * basis_.size());
    tbb::parallel_for(size_t(0), basis_.size(), [&](size_t i) {
      const auto& [u, v, d] = basis_[i];
      glm::vec4 extent(0.0f, 0.0f, radius, radius);  // centre u, centre v, half-widths
      if (fit) {
        const float inf = std::numeric_limits<float>::infinity();
        glm::vec2 lo(inf), hi(-inf);
        for (const glm::vec3& p : receivers) {
          const glm::vec2 uv(glm::dot(p - c, u), glm::dot(p - c, v));
          lo = glm::min(lo, uv);
          hi = glm::max(hi, uv);
        }
        const float widen = 1.0f + 4.0f / static_cast<float>(s_.resolution);
        const glm::vec2 half =
            glm::max(0.5f * (hi - lo), glm::vec2(1e-3f * radius)) * widen + 1e-6f * radius;
        extent = glm::vec4(0.5f * (lo + hi), half);
      }
      const float texel_scale = std::max(extent.z, extent.w) / radius;
      out[4 * i] = glm::vec4(u, 0.0f);
      out[4 * i + 1] = glm::vec4(v, 0.0f);
      out[4 * i + 2] = glm::vec4(d, texel_scale);
      out[4 * i + 3] = glm::vec4(extent.x, extent.y, 1.0f / extent.z, 1.0f / extent.w);
    });
    return out;
  }

  void make_accumulators() {
    accumulators_ =
        vk::Buffer(vk_, std::max<VkDeviceSize>(1, receiver_count_) * 4 * sizeof(glm::vec4),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  }

  vk::Context& vk_;
  ShadowmapSettings s_;
  vk::PassTimer timer_;
  glm::vec4 centre_radius_{0.0f};
  std::vector<std::array<glm::vec3, 3>> basis_;  // per light: u, v, d
  uint32_t vertex_count_ = 0, receiver_count_ = 0, width_ = 1;
  vk::Buffer positions_, indices_, lights_, receivers_, accumulators_;
  std::unique_ptr<vk::GraphicsPipeline> depth_pipeline_;
  VkDescriptorSet depth_set_ = VK_NULL_HANDLE, set_ = VK_NULL_HANDLE;
  vk::Image2D atlas_, atlas_depth_, dummy_;
  std::unique_ptr<vk::Framebuffer> framebuffer_;
  std::unique_ptr<vk::ComputePipeline> accumulate_;
  vk::DeviceGBuffer gbuffer_;
};

// Mode vertex: the bake of §17.2's shape with §17.3's visibility. Every triangle's centre and face
// normal is a receiver with two sides; the per-triangle values are area-averaged to the vertices
// as vertex_bake.cpp does, into a VertexBake that vertex_bake's lookup() interpolates.
VertexBake bake_with_shadow_maps(const Scene& scene, ShadowmapDevice& device) {
  std::vector<glm::vec4> receivers;
  std::vector<float> areas;
  for (const SceneObject& o : scene.objects)
    for (const glm::uvec3& t : o.mesh.triangles) {
      const glm::vec3 p0 = o.mesh.positions[t.x], p1 = o.mesh.positions[t.y],
                      p2 = o.mesh.positions[t.z];
      const glm::vec3 c = glm::cross(p1 - p0, p2 - p0);
      const float len = glm::length(c);
      const bool ok = len > 0.0f && std::isfinite(len);  // degenerate: no hemisphere, weight 0
      receivers.push_back(glm::vec4((p0 + p1 + p2) / 3.0f, ok ? 1.0f : 0.0f));
      receivers.push_back(glm::vec4(ok ? c / len : glm::vec3(0.0f), 0.0f));
      areas.push_back(ok ? 0.5f * len : 0.0f);
    }
  device.set_receivers(receivers);
  std::map<std::string, double> unused;
  const std::vector<SideSums> sums = device.accumulate(unused);
  VertexBake bake;
  bake.objects.resize(scene.objects.size());
  size_t r = 0;
  for (size_t geom = 0; geom < scene.objects.size(); ++geom) {
    const TriangleMesh& mesh = scene.objects[geom].mesh;
    BakedMesh& bm = bake.objects[geom];
    bm.positions = mesh.positions;
    bm.triangles = mesh.triangles;
    const size_t nv = bm.positions.size();
    std::vector<double> weight(nv, 0.0);
    std::vector<double> acc[2] = {std::vector<double>(nv, 0.0), std::vector<double>(nv, 0.0)};
    std::vector<glm::dvec3> bent[2] = {std::vector<glm::dvec3>(nv, glm::dvec3(0.0)),
                                       std::vector<glm::dvec3>(nv, glm::dvec3(0.0))};
    for (size_t t = 0; t < bm.triangles.size(); ++t, ++r) {
      const double w = areas[r];
      float a[2];
      glm::vec3 b[2];
      for (int side = 0; side < 2; ++side) resolve(sums[2 * r + side], a[side], b[side]);
      for (int corner = 0; corner < 3; ++corner) {
        const uint32_t v = bm.triangles[t][corner];
        weight[v] += w;
        for (int side = 0; side < 2; ++side) {
          acc[side][v] += w * a[side];
          bent[side][v] += w * glm::dvec3(b[side]);
        }
      }
    }
    for (int side = 0; side < 2; ++side) {
      bm.accessibility[side].resize(nv);
      bm.bent[side].resize(nv);
      for (size_t v = 0; v < nv; ++v) {
        const bool any = weight[v] > 0.0;
        bm.accessibility[side][v] = any ? static_cast<float>(acc[side][v] / weight[v]) : 1.0f;
        bm.bent[side][v] = any ? glm::vec3(bent[side][v] / weight[v]) : glm::vec3(0.0f);
      }
    }
  }
  return bake;
}

class ShadowmapAoEstimator : public Estimator {
 public:
  explicit ShadowmapAoEstimator(const ParamSet& p) : settings_(shadowmap_settings(p)) {}

  void prepare(const EstimateContext& context) override {
    vk::Context& vk = vk::require_shared_context();
    device_.reset();
    bake_.reset();
    device_ = std::make_unique<ShadowmapDevice>(vk, context.scene, settings_);
    if (settings_.mode == ShadowmapMode::vertex) {
      bake_ = bake_with_shadow_maps(context.scene, *device_);
      device_.reset();  // the bake is all a frame needs
    } else {
      device_->set_gbuffer(context.gbuffer);
    }
  }

  EstimateResult run(const EstimateContext& context) override {
    if (!device_ && !bake_) throw std::logic_error("shadowmap-ao: run() without prepare()");
    const GBuffer& g = context.gbuffer;
    const size_t n = g.pixel_count();
    EstimateResult r;
    r.ao.assign(n, 0.0f);
    std::vector<float> bx(n, 0.0f), by(n, 0.0f), bz(n, 0.0f);
    if (settings_.mode == ShadowmapMode::pixel) {
      const std::vector<SideSums> sums = device_->accumulate(r.pass_ms);
      for (size_t k = 0; k < n; ++k) {
        if (!g.covered(k)) continue;
        glm::vec3 b;
        resolve(sums[2 * k], r.ao[k], b);
        bx[k] = b.x, by[k] = b.y, bz[k] = b.z;
      }
    } else {
      interpolate(context, r.ao, bx, by, bz);
    }
    r.extra_channels["bent.X"] = std::move(bx);
    r.extra_channels["bent.Y"] = std::move(by);
    r.extra_channels["bent.Z"] = std::move(bz);
    return r;
  }

 private:
  // Mode vertex, per frame: the pixel's triangle and barycentrics from its primary ray (the
  // G-buffer keeps neither), then §17.4's interpolation, exactly as vertex-baked does.
  void interpolate(const EstimateContext& context, std::vector<float>& ao, std::vector<float>& bx,
                   std::vector<float>& by, std::vector<float>& bz) const {
    const GBuffer& g = context.gbuffer;
    const Camera& camera = g.camera;
    const VertexBake& bake = *bake_;
    if (bake.objects.size() != context.scene.objects.size())
      throw std::logic_error("shadowmap-ao: run() on another scene than prepare()");
    parallel_for_embree(
        tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& rows) {
          RTCIntersectContext ctx;
          rtcInitIntersectContext(&ctx);
          for (int j = rows.begin(); j < rows.end(); ++j)
            for (int i = 0; i < g.width; ++i) {
              const size_t k = g.index(i, j);
              if (!g.covered(k)) continue;
              const glm::vec3 dir = camera.direction(i, j);
              RTCRayHit rh{};
              rh.ray.org_x = camera.eye.x, rh.ray.org_y = camera.eye.y, rh.ray.org_z = camera.eye.z;
              rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
              rh.ray.tfar = std::numeric_limits<float>::infinity();
              rh.ray.mask = 0xFFFFFFFFu;
              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
              rtcIntersect1(context.embree.handle(), &ctx, &rh);
              if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                ao[k] = 1.0f;
                continue;
              }
              const TriangleMesh& mesh = context.scene.objects[rh.hit.geomID].mesh;
              const glm::uvec3 tri = mesh.triangles[rh.hit.primID];
              const glm::vec3 p0 = mesh.positions[tri.x];
              const glm::vec3 ng =
                  glm::cross(mesh.positions[tri.y] - p0, mesh.positions[tri.z] - p0);
              const int side = glm::dot(ng, dir) > 0.0f ? 1 : 0;  // the viewer's side
              const BakedSample s =
                  lookup(bake, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, side);
              ao[k] = s.accessibility;
              bx[k] = s.bent.x, by[k] = s.bent.y, bz[k] = s.bent.z;
            }
        });
  }

  ShadowmapSettings settings_;
  std::unique_ptr<ShadowmapDevice> device_;
  std::optional<VertexBake> bake_;
};

}  // namespace

ShadowmapSettings shadowmap_settings(const ParamSet& p) {
  ShadowmapSettings s;
  s.lights = static_cast<int>(p.integer("lights"));
  s.resolution = static_cast<int>(p.integer("resolution"));
  s.distribution = p.choice("distribution") == "latlong" ? LightDistribution::latlong
                                                         : LightDistribution::uniform;
  s.dome = p.choice("layout") == "dome";
  s.bias = static_cast<float>(p.real("bias"));
  s.slope_bias = static_cast<float>(p.real("slope_bias"));
  s.lights_per_pass = static_cast<int>(p.integer("lights_per_pass"));
  s.weighting = parse_weighting(p.choice("weighting"), "weighting");
  s.mode = p.choice("mode") == "vertex" ? ShadowmapMode::vertex : ShadowmapMode::pixel;
  s.fit_receivers = p.choice("fit") == "receivers";
  s.seed = static_cast<uint64_t>(p.integer("seed"));
  return s;
}

EstimatorInfo shadowmap_ao_estimator() {
  EstimatorInfo info;
  info.name = "shadowmap-ao";
  info.summary =
      "accessibility from n shadow-mapped directional lights around the scene (GPU Gems ch. 17)";
  info.paper =
      "Pharr and Green 2004, GPU Gems ch. 17, Ambient Occlusion: §17.3 Hardware-Accelerated "
      "Occlusion (a spherical array of shadow-mapped lights, uniform vs. lat-long placement, dome, "
      "several shadow maps per accumulation pass, bent normal), §17.2/§17.4 for the per-vertex "
      "bake";
  info.backend = Backend::vulkan;
  // Measured quiet (sweep, warm-up 0, 7 repetitions, bunny, dragon, cornell-box, sphere-uniform):
  // its first run is 0.98-1.03x the median of the other six (prepare() builds its pipelines and
  // buffers, and in vertex mode the bake), so a warm-up run bought nothing and cost about 5 s of a
  // cold default run.
  info.first_run_is_warm = true;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::scene_geometry};
  info.params = {
      int_param({.name = "lights",
                 .def = 256,
                 .min = 1,
                 .max = 4096,
                 .spacing = Spacing::log,
                 .unit = "lights",
                 .meaning =
                     "shadow-casting directional lights (§17.3: \"128 to 1024 is required for good "
                     "results\")"}),
      int_param(
          {.name = "resolution",
           .def = 512,
           .min = 16,
           .max = 4096,
           .spacing = Spacing::log,
           .unit = "texels",
           .meaning = "texels per side of each light's orthographic shadow map (its extent: fit)"}),
      choice_param(
          {.name = "fit",
           .def = "receivers",
           .choices = {"receivers", "scene"},
           .meaning =
               "each light's map laterally: receivers = the extent of the receivers as that light "
               "sees "
               "them (mode pixel: the covered G-buffer points; vertex: the baked triangle "
               "centres), as "
               "cascaded shadow maps fit the view; scene = the scene's bounding sphere (GPU Gems' "
               "whole-object map, which spends the texels on what no receiver needs). Depth covers "
               "the "
               "sphere either way, so every occluder is drawn"}),
      choice_param(
          {.name = "distribution",
           .def = "uniform",
           .choices = {"uniform", "latlong"},
           .meaning =
               "light placement: uniform (spherical Fibonacci lattice under a seeded rotation, "
               "§17.3's "
               "\"uniform distribution on the sphere\") or latlong (evenly spaced latitudes and "
               "longitudes, which \"concentrate too many samples at the poles\")"}),
      choice_param(
          {.name = "layout",
           .def = "sphere",
           .choices = {"sphere", "dome"},
           .meaning = "sphere, or dome: lights over the +Y hemisphere only, the ground assumed to "
                      "block the rest "
                      "(§17.3: \"a dome or a hemisphere can be used instead\")"}),
      real_param({.name = "bias",
                  .def = 1.0,
                  .min = 0.0,
                  .max = 64.0,
                  .spacing = Spacing::linear,
                  .unit = "texels",
                  .meaning = "constant depth bias of the shadow test at the receiver"}),
      real_param({.name = "slope_bias",
                  .def = 1.0,
                  .min = 0.0,
                  .max = 64.0,
                  .spacing = Spacing::linear,
                  .unit = "texels",
                  .meaning = "slope-scaled depth bias: slope_bias * tan(angle between light and "
                             "surface normal), tan "
                             "capped at 1000 (§17.3's \"streaking ... at the transition from lit "
                             "to shadowed\")"}),
      int_param({.name = "lights_per_pass",
                 .def = 8,
                 .min = 1,
                 .max = 16,
                 .spacing = Spacing::linear,
                 .unit = "lights",
                 .meaning = "shadow maps tested in one accumulation pass (§17.3: \"accumulate "
                            "eight shadows in the "
                            "shader at once\")"}),
      choice_param({.name = "weighting",
                    .def = "uniform",
                    .choices = {"uniform", "cosine"},
                    .meaning = "uniform: every light above the surface counts 1 (the chapter's "
                               "accessibility); cosine: "
                               "each counts n.l, estimating the cosine-weighted AO"}),
      choice_param(
          {.name = "mode",
           .def = "pixel",
           .choices = {"pixel", "vertex"},
           .meaning =
               "pixel: every camera G-buffer pixel is a receiver; vertex: triangle centres baked, "
               "area-averaged to vertices and interpolated per pixel (§17.2, §17.4), as "
               "vertex-baked"}),
      seed_param("random seed of the lights' rotation"),
  };
  info.definition_doc = "the weighting parameter's (uniform or cosine), unbounded, no falloff";
  info.definition = [](const ParamSet& p) {
    AoDefinition d;
    d.weighting = parse_weighting(p.choice("weighting"), "weighting");
    return d;
  };
  info.create = [](const ParamSet& p) { return std::make_unique<ShadowmapAoEstimator>(p); };
  return info;
}

}  // namespace aoeval
