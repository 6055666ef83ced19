#include "estimators/vulkan/raster_gbuffer.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <vector>

#include "raster_gbuffer_frag_spv.h"
#include "raster_gbuffer_vert_spv.h"
#include "scenes/instances.h"

namespace aoeval::vk {

namespace {

constexpr VkImageUsageFlags kAttachment = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;

// Matches the push_constant block of raster_gbuffer.vert/.frag (std430 offsets 0..68).
struct RasterPush {
  float eye_near[4];
  float forward_tan[4];
  float right_width[4];
  float up_height[4];
  int32_t object_id;
  uint32_t has_normals;
};
static_assert(sizeof(RasterPush) == 72);

struct DrawRange {
  uint32_t first_vertex = 0;  // 3 * first triangle
  uint32_t vertex_count = 0;  // 3 * triangles
  int32_t object_id = 0;
  bool has_normals = false;
};

}  // namespace

DeviceGBuffer make_device_gbuffer(Context& context, int width, int height) {
  DeviceGBuffer d;
  d.width = width;
  d.height = height;
  d.coverage = Image2D(context, width, height, VK_FORMAT_R32_SFLOAT, kAttachment);
  d.depth = Image2D(context, width, height, VK_FORMAT_R32_SFLOAT, kAttachment);
  d.position = Image2D(context, width, height, VK_FORMAT_R32G32B32A32_SFLOAT, kAttachment);
  d.normal = Image2D(context, width, height, VK_FORMAT_R32G32B32A32_SFLOAT, kAttachment);
  d.geometric_normal = Image2D(context, width, height, VK_FORMAT_R32G32B32A32_SFLOAT, kAttachment);
  d.object_id = Image2D(context, width, height, VK_FORMAT_R32_SFLOAT, kAttachment);
  return d;
}

namespace {

std::vector<float> rgba(const std::vector<glm::vec3>& v, const std::vector<float>& w) {
  std::vector<float> out(4 * v.size());
  for (size_t k = 0; k < v.size(); ++k) {
    out[4 * k] = v[k].x;
    out[4 * k + 1] = v[k].y;
    out[4 * k + 2] = v[k].z;
    out[4 * k + 3] = w.empty() ? 0.0f : w[k];
  }
  return out;
}

std::vector<glm::vec3> xyz(const std::vector<float>& rgba_values) {
  std::vector<glm::vec3> out(rgba_values.size() / 4);
  for (size_t k = 0; k < out.size(); ++k)
    out[k] = {rgba_values[4 * k], rgba_values[4 * k + 1], rgba_values[4 * k + 2]};
  return out;
}

}  // namespace

DeviceGBuffer upload_gbuffer(Context& context, const GBuffer& g) {
  DeviceGBuffer d = make_device_gbuffer(context, g.width, g.height);
  d.coverage.upload(g.coverage);
  d.depth.upload(g.depth);
  d.position.upload(rgba(g.position, g.coverage));
  d.normal.upload(rgba(g.normal, {}));
  d.geometric_normal.upload(rgba(g.geometric_normal, {}));
  d.object_id.upload(g.object_id);
  return d;
}

GBuffer download_gbuffer(const DeviceGBuffer& d, const Camera& camera) {
  GBuffer g;
  g.width = d.width;
  g.height = d.height;
  g.camera = camera;
  g.coverage = d.coverage.download<float>();
  g.depth = d.depth.download<float>();
  g.position = xyz(d.position.download<float>());
  g.normal = xyz(d.normal.download<float>());
  g.geometric_normal = xyz(d.geometric_normal.download<float>());
  g.object_id = d.object_id.download<float>();
  return g;
}

namespace {

GraphicsDesc pipeline_desc() {
  GraphicsDesc d;
  d.name = "raster_gbuffer";
  d.vertex = raster_gbuffer_vert_spv;
  d.fragment = raster_gbuffer_frag_spv;
  d.bindings = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};  // positions, indices, normals
  d.push_constant_bytes = sizeof(RasterPush);
  // The order of DeviceGBuffer and of the fragment shader's outputs.
  d.color_formats = {VK_FORMAT_R32_SFLOAT,          VK_FORMAT_R32_SFLOAT,
                     VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT,
                     VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32_SFLOAT};
  return d;
}

}  // namespace

struct RasterGBuffer::Impl {
  Context& context;
  Bounds bounds;
  Buffer positions, indices, normals;
  std::vector<DrawRange> draws;
  GraphicsPipeline pipeline;
  VkDescriptorSet set = VK_NULL_HANDLE;
  // The depth attachment (kept while the size stays) and the framebuffer of the last record()
  // (made anew each time: the target may be a different DeviceGBuffer; submissions are synchronous,
  // so the previous one is no longer in use).
  Image2D depth;
  std::unique_ptr<Framebuffer> framebuffer;

  Impl(Context& ctx, const Scene& scene)
      : context(ctx), bounds(scene.bounds()), pipeline(ctx, pipeline_desc()) {
    // Instanced draws are not built yet: one clear refusal instead of a G-buffer that lacks them.
    refuse_instances(scene,
                     "the Vulkan raster G-buffer (gbuffer=raster; --set gbuffer=embree takes "
                     "instanced scenes)");
    // One global vertex array (objects concatenated, world space) and one global index array; an
    // object without shading normals gets zeros there and has_normals = 0 (the shader uses Ng).
    std::vector<float> p, n;
    std::vector<uint32_t> idx;
    for (size_t o = 0; o < scene.objects.size(); ++o) {
      const TriangleMesh& mesh = scene.objects[o].mesh;
      const uint32_t base = static_cast<uint32_t>(p.size() / 3);
      DrawRange draw;
      draw.first_vertex = static_cast<uint32_t>(idx.size());
      draw.vertex_count = static_cast<uint32_t>(3 * mesh.triangle_count());
      draw.object_id = static_cast<int32_t>(o);
      draw.has_normals = !mesh.normals.empty();
      for (size_t v = 0; v < mesh.positions.size(); ++v) {
        for (int c = 0; c < 3; ++c) {
          p.push_back(mesh.positions[v][c]);
          n.push_back(draw.has_normals ? mesh.normals[v][c] : 0.0f);
        }
      }
      for (const glm::uvec3& t : mesh.triangles)
        for (int c = 0; c < 3; ++c) idx.push_back(base + t[c]);
      if (draw.vertex_count > 0) draws.push_back(draw);
    }
    if (idx.empty()) throw VulkanError("raster G-buffer: the scene has no triangles");
    positions = storage_buffer(ctx, p);
    indices = storage_buffer(ctx, idx);
    normals = storage_buffer(ctx, n);
    set = pipeline.make_set({positions, indices, normals});
  }

  // Near plane of the reversed-Z projection: far below the G-buffer's float precision (1e-6 of the
  // farthest scene point), so nothing Embree would hit (its tnear is 0) is clipped in practice.
  float near_plane(const Camera& camera) const {
    float far = 0.0f;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner{k & 1 ? bounds.upper.x : bounds.lower.x,
                             k & 2 ? bounds.upper.y : bounds.lower.y,
                             k & 4 ? bounds.upper.z : bounds.lower.z};
      far = std::max(far, glm::length(corner - camera.eye));
    }
    return std::max(far * 1e-6f, 1e-30f);
  }
};

RasterGBuffer::RasterGBuffer(Context& context, const Scene& scene)
    : impl_(std::make_unique<Impl>(context, scene)) {}

RasterGBuffer::~RasterGBuffer() = default;

void RasterGBuffer::record(VkCommandBuffer cmd, const Camera& camera, DeviceGBuffer& target,
                           PassTimer* timer) {
  Impl& m = *impl_;
  if (target.width != camera.width || target.height != camera.height)
    throw VulkanError("raster G-buffer: target size differs from the camera's");
  // The rasteriser samples pixel centres; a jittered sequence frame (CONTRACT §10 "halton") would
  // need a sub-pixel offset in the projection and the fragment's ray, which this pass lacks.
  if (camera.jitter != glm::vec2(0.0f))
    throw VulkanError(
        "raster G-buffer: jittered cameras are not supported (use the Embree G-buffer)");
  m.framebuffer.reset();
  if (!m.depth.valid() || m.depth.width() != target.width || m.depth.height() != target.height)
    m.depth = Image2D(m.context, target.width, target.height, VK_FORMAT_D32_SFLOAT);
  m.framebuffer = std::make_unique<Framebuffer>(
      m.context, m.pipeline,
      std::vector<const Image2D*>{&target.coverage, &target.depth, &target.position, &target.normal,
                                  &target.geometric_normal, &target.object_id},
      m.depth);
  RasterPush push{};
  const float near = m.near_plane(camera);
  for (int c = 0; c < 3; ++c) {
    push.eye_near[c] = camera.eye[c];
    push.forward_tan[c] = camera.forward[c];
    push.right_width[c] = camera.right[c];
    push.up_height[c] = camera.up[c];
  }
  push.eye_near[3] = near;
  push.forward_tan[3] = camera.tan_half_fov_y;
  push.right_width[3] = static_cast<float>(camera.width);
  push.up_height[3] = static_cast<float>(camera.height);

  if (timer) timer->begin(cmd, "geometry", PassTimer::Work::draws);
  const VkClearColorValue zero{{0.0f, 0.0f, 0.0f, 0.0f}};
  const VkClearColorValue minus_one{{-1.0f, 0.0f, 0.0f, 0.0f}};
  m.framebuffer->begin(cmd, m.pipeline, {zero, zero, zero, zero, zero, minus_one}, 0.0f);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.pipeline.layout(), 0, 1, &m.set,
                          0, nullptr);
  for (const DrawRange& d : m.draws) {
    push.object_id = d.object_id;
    push.has_normals = d.has_normals ? 1u : 0u;
    m.pipeline.push(cmd, &push, sizeof(push));
    vkCmdDraw(cmd, d.vertex_count, 1, d.first_vertex, 0);
  }
  m.framebuffer->end(cmd);
  pass_barrier(cmd);
  if (timer) timer->end(cmd);
}

GBuffer RasterGBuffer::render(const Camera& camera) {
  DeviceGBuffer target = make_device_gbuffer(impl_->context, camera.width, camera.height);
  impl_->context.submit([&](VkCommandBuffer cmd) { record(cmd, camera, target); });
  impl_->framebuffer.reset();  // it names `target`'s views, which die here
  return download_gbuffer(target, camera);
}

}  // namespace aoeval::vk
