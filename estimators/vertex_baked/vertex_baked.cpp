#include "estimators/vertex_baked/vertex_baked.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <limits>
#include <optional>
#include <stdexcept>

#include "base/errors.h"
#include "estimators/seed_param.h"
#include "estimators/vertex_baked/vertex_bake.h"

namespace aoeval {

namespace {

class VertexBakedEstimator : public Estimator {
 public:
  explicit VertexBakedEstimator(const ParamSet& p) {
    settings_.rays = static_cast<int>(p.integer("rays"));
    settings_.subdivide = static_cast<int>(p.integer("subdivide"));
    settings_.sampler = parse_sampler(p.choice("sampler"));
    settings_.seed = static_cast<uint64_t>(p.integer("seed"));
  }

  // The view-independent preprocess of §17.2.
  void prepare(const EstimateContext& context) override {
    bake_ = bake_vertices(context.scene, context.embree, settings_);
  }

  EstimateResult run(const EstimateContext& context) override {
    if (!bake_ || bake_->objects.size() != context.scene.objects.size())
      throw std::logic_error("vertex-baked: run() without prepare() on this scene");
    const GBuffer& g = context.gbuffer;
    const Camera& camera = g.camera;
    if (camera.width != g.width || camera.height != g.height)
      throw InputError("gbuffer: its camera (" + std::to_string(camera.width) + "x" +
                       std::to_string(camera.height) + ") does not match its size (" +
                       std::to_string(g.width) + "x" + std::to_string(g.height) + ")");
    const size_t n = g.pixel_count();
    EstimateResult r;
    r.ao.assign(n, 0.0f);
    std::vector<float> bx(n, 0.0f), by(n, 0.0f), bz(n, 0.0f);
    const VertexBake& bake = *bake_;
    const Scene& scene = context.scene;
    parallel_for_embree(
        tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& rows) {
          RTCIntersectContext ctx;
          rtcInitIntersectContext(&ctx);
          for (int j = rows.begin(); j < rows.end(); ++j) {
            for (int i = 0; i < g.width; ++i) {
              const size_t k = g.index(i, j);
              if (!g.covered(k)) continue;
              // The G-buffer keeps no triangle id or barycentrics: re-trace its primary ray (same
              // camera, same scene, so the same hit) to find them, as a rasteriser would have them.
              const glm::vec3 dir = camera.direction(i, j);
              RTCRayHit rh{};
              rh.ray.org_x = camera.eye.x, rh.ray.org_y = camera.eye.y, rh.ray.org_z = camera.eye.z;
              rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
              rh.ray.tnear = 0.0f;
              rh.ray.tfar = std::numeric_limits<float>::infinity();
              rh.ray.mask = 0xFFFFFFFFu;
              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
              rtcIntersect1(context.embree.handle(), &ctx, &rh);
              if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                r.ao[k] = 1.0f;  // cannot happen with the G-buffer of this scene and camera
                continue;
              }
              const TriangleMesh& mesh = scene.objects[rh.hit.geomID].mesh;
              const glm::uvec3 tri = mesh.triangles[rh.hit.primID];
              const glm::vec3 p0 = mesh.positions[tri.x];
              const glm::vec3 ng =
                  glm::cross(mesh.positions[tri.y] - p0, mesh.positions[tri.z] - p0);
              // The viewer's side, by render_gbuffer's own test: the side the G-buffer normal
              // faces.
              const int side = glm::dot(ng, dir) > 0.0f ? 1 : 0;
              const BakedSample s =
                  lookup(bake, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, side);
              r.ao[k] = s.accessibility;
              bx[k] = s.bent.x, by[k] = s.bent.y, bz[k] = s.bent.z;
            }
          }
        });
    r.extra_channels["bent.X"] = std::move(bx);
    r.extra_channels["bent.Y"] = std::move(by);
    r.extra_channels["bent.Z"] = std::move(bz);
    return r;
  }

 private:
  BakeSettings settings_{};
  std::optional<VertexBake> bake_;
};

}  // namespace

EstimatorInfo vertex_baked_estimator() {
  EstimatorInfo info;
  info.name = "vertex-baked";
  info.summary =
      "per-vertex accessibility ray traced at triangle centres and interpolated (GPU Gems ch. 17)";
  info.paper =
      "Pharr and Green 2004, GPU Gems ch. 17, Ambient Occlusion: §17.2 Listing 17-1 (accessibility "
      "and bent normal per triangle, averaged to vertices), §17.4 (interpolated per pixel)";
  info.backend = Backend::embree;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::scene_geometry};
  info.params = {
      int_param({.name = "rays",
                 .def = 128,
                 .min = 1,
                 .max = 65536,
                 .spacing = Spacing::log,
                 .unit = "rays",
                 .meaning = "rays per triangle and side at its centre (§17.2, Listing 17-1; the "
                            "chapter used 512)"}),
      int_param({.name = "subdivide",
                 .def = 0,
                 .min = 0,
                 .max = 6,
                 .spacing = Spacing::linear,
                 .unit = "levels",
                 .meaning = "1:4 midpoint splits of every triangle before baking; 0 = as modelled "
                            "(§17.2 assumes a "
                            "finely tessellated model)"}),
      choice_param({.name = "sampler",
                    .def = "random",
                    .choices = {"random", "stratified", "sobol"},
                    .meaning = "hemisphere points: random (Listing 17-2's distribution), "
                               "stratified or sobol (§17.2 "
                               "\"more complex Monte Carlo sampling\")"}),
      seed_param("random seed of the bake"),
  };
  info.definition_doc = "uniform weighting, unbounded (GPU Gems ch. 17 accessibility), always";
  info.definition = [](const ParamSet&) {
    AoDefinition d;
    d.weighting = Weighting::uniform;
    return d;
  };
  info.create = [](const ParamSet& p) { return std::make_unique<VertexBakedEstimator>(p); };
  return info;
}

}  // namespace aoeval
