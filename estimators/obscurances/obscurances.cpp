// Ray-traced obscurances (Méndez, Sbert, Catà 2003): grey W(P) of eq. 2 and colour-bleeding
// W_rgb(P) of eq. 5-6, Nobs cosine-distributed Embree rays per pixel. See obscurances.h.
#include "estimators/obscurances/obscurances.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "base/errors.h"
#include "estimators/power_falloff_param.h"
#include "estimators/seed_param.h"
#include "sampling/ray_offset.h"
#include "scenes/instances.h"

namespace aoeval {

namespace {

// The ray's first hit: the distance (inf when nothing lies within dmax) and the object hit.
struct Hit {
  float distance;
  unsigned object;
};

// rho = constant only needs to know whether something lies within dmax (its value is 0 for any
// hit, and so is its colour, eq. 5): an occlusion ray. The other families need the distance.
Hit trace(RTCScene scene, RTCIntersectContext& context, const glm::vec3& o, const glm::vec3& w,
          float tfar, bool distance_needed) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  if (!distance_needed) {
    RTCRay ray{};
    ray.org_x = o.x, ray.org_y = o.y, ray.org_z = o.z;
    ray.dir_x = w.x, ray.dir_y = w.y, ray.dir_z = w.z;
    ray.tnear = 0.0f;
    ray.tfar = tfar;
    ray.mask = 0xFFFFFFFFu;
    rtcOccluded1(scene, &context, &ray);
    return {ray.tfar < 0.0f ? 0.0f : kInf, RTC_INVALID_GEOMETRY_ID};  // tfar = -inf on a hit
  }
  RTCRayHit rh{};
  rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
  rh.ray.dir_x = w.x, rh.ray.dir_y = w.y, rh.ray.dir_z = w.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = tfar;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {kInf, RTC_INVALID_GEOMETRY_ID};
  return {rh.ray.tfar, hit_placement(rh.hit)};
}

AoDefinition definition_of(const ObscuranceSettings& s) {
  AoDefinition d;  // cosine weighting: the cos(theta)/pi of eq. 2
  d.dmax = s.dmax;
  d.falloff = s.rho;
  return d;
}

}  // namespace

ObscuranceSettings obscurance_settings_of(const ParamSet& p) {
  ObscuranceSettings s{};
  s.rays = static_cast<int>(p.integer("rays"));
  s.dmax = p.real("dmax");
  const double k = p.real("rho_k");  // read always: every declared parameter is read
  s.rho = p.choice("rho") == "power" ? Falloff::power(k) : parse_rho(p.choice("rho"));
  s.sampling = p.choice("sampling") == "systematic" ? SamplerKind::stratified : SamplerKind::random;
  s.seed = static_cast<uint64_t>(p.integer("seed"));
  return s;
}

namespace {

class ObscurancesEstimator : public Estimator {
 public:
  explicit ObscurancesEstimator(const ParamSet& p) : settings_(obscurance_settings_of(p)) {}
  void prepare(const EstimateContext& context) override {
    r_ave_ = average_reflectivity(context.scene);
    prepared_ = true;
  }
  EstimateResult run(const EstimateContext& context) override {
    if (!prepared_) prepare(context);
    ObscuranceImage image = compute_obscurances(context.embree, context.gbuffer, settings_, r_ave_);
    EstimateResult r;
    r.ao = std::move(image.grey);
    const char* names[3] = {"obscurance.R", "obscurance.G", "obscurance.B"};
    for (int c = 0; c < 3; ++c) {
      std::vector<float>& channel = r.extra_channels[names[c]];
      channel.resize(image.rgb.size());
      for (size_t k = 0; k < image.rgb.size(); ++k) channel[k] = image.rgb[k][c];
    }
    return r;
  }

 private:
  ObscuranceSettings settings_;
  glm::vec3 r_ave_{0.0f};
  bool prepared_ = false;
};

}  // namespace

Falloff parse_rho(const std::string& name) {
  if (name == "exp") return Falloff::exp;
  if (name == "sqrt") return Falloff::sqrt;
  if (name == "constant") return Falloff::none;
  throw InputError("rho: '" + name + "' is not one of: exp, sqrt, constant");
}

glm::vec3 average_reflectivity(const Scene& scene) {
  glm::dvec3 weighted(0.0), plain(0.0);
  double total = 0.0;
  for (const SceneObject& o : scene.objects) {
    double area = 0.0;
    for (const glm::uvec3& t : o.mesh.triangles) {
      const glm::dvec3 a(o.mesh.positions[t.x]), b(o.mesh.positions[t.y]), c(o.mesh.positions[t.z]);
      area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    weighted += area * glm::dvec3(o.albedo);
    plain += glm::dvec3(o.albedo);
    total += area;
  }
  if (scene.objects.empty()) return glm::vec3(0.0f);
  // Degenerate geometry only (zero total area): fall back to the plain mean of the albedos.
  return total > 0.0 ? glm::vec3(weighted / total)
                     : glm::vec3(plain / static_cast<double>(scene.objects.size()));
}

ObscuranceImage compute_obscurances(const EmbreeScene& es, const GBuffer& g,
                                    const ObscuranceSettings& s, glm::vec3 r_ave) {
  if (s.rays < 1) throw InputError("rays: must be at least 1");
  if (!(s.dmax > 0.0) || !std::isfinite(s.dmax))
    throw InputError("dmax: must be a positive finite distance (eq. 2's range)");
  const AoDefinition def = definition_of(s);
  const Scene& scene = es.scene();
  // R(Q) by placement id (embree_scene.h hit_placement; = object index without instances).
  std::vector<glm::vec3> albedo;
  for (const SceneObject& o : scene.objects)
    albedo.insert(albedo.end(), std::max<size_t>(1, o.instances.size()), o.albedo);
  const glm::vec3 e = scene.bounds().extent();
  const float extent = std::max({e.x, e.y, e.z});
  const auto tfar = static_cast<float>(s.dmax);
  const bool distance_needed = s.rho != Falloff::none;
  const auto m = static_cast<uint32_t>(s.rays);

  ObscuranceImage out;
  out.average_reflectivity = r_ave;
  out.grey.assign(g.pixel_count(), 0.0f);
  out.rgb.assign(g.pixel_count(), glm::vec3(0.0f));
  parallel_for_embree(
      tbb::blocked_range<int>(0, g.height, 1), [&](const tbb::blocked_range<int>& rows) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        std::vector<glm::vec2> square(m);
        for (int j = rows.begin(); j < rows.end(); ++j) {
          for (int i = 0; i < g.width; ++i) {
            const size_t k = g.index(i, j);
            if (!g.covered(k)) continue;
            const glm::vec3 p = g.position[k], ng = g.geometric_normal[k];
            const glm::vec3 o = p + ng * origin_offset(p, extent);
            const Frame frame = make_frame(g.normal[k]);
            // The same stream as the reference's (pixel k, replicate 0): only the seed differs.
            sample_square(s.sampling, s.seed, k, 0, m, square.data());
            double sum = 0.0;  // fixed order per pixel: deterministic whatever the threads
            glm::dvec3 rgb(0.0);
            for (uint32_t n = 0; n < m; ++n) {
              const glm::vec3 w = frame.to_world(square_to_cosine_hemisphere(square[n]));
              // Below the geometric surface: a hit at distance 0, worth rho(0) = 0 (grey and
              // colour alike).
              if (!(glm::dot(w, ng) > 0.0f)) continue;
              const Hit hit = trace(es.handle(), context, o, w, tfar, distance_needed);
              const float v = def.ray_value(hit.distance);  // eq. 2: rho(d/dmax), 1 beyond dmax
              sum += v;
              if (!(hit.distance < def.dmax))
                rgb += glm::dvec3(r_ave);  // eq. 6: nothing within dmax -> R_ave
              else if (distance_needed)
                rgb += glm::dvec3(albedo[hit.object] * v);  // eq. 5: R(Q) rho(d/dmax)
              // else rho = constant: a hit within dmax is worth R(Q) * 0 = 0.
            }
            out.grey[k] = static_cast<float>(sum / m);
            out.rgb[k] = glm::vec3(rgb / static_cast<double>(m));
          }
        }
      });
  return out;
}

EstimatorInfo obscurances_estimator() {
  EstimatorInfo info;
  info.name = "obscurances";
  info.summary =
      "ray-traced obscurances: Nobs cosine rays, rho(d/dmax) per ray, RGB colour bleeding";
  info.paper =
      "Mendez, Sbert, Cata 2003, Ray-traced obscurances: eq. 2 (W(P), grey, the AO output), "
      "eq. 3 (R_ave), eq. 5-6 (colour bleeding: R(Q) rho per hit, R_ave when nothing within dmax; "
      "extra channels obscurance.R/G/B), §3 (rho families), §4.2 (systematic sampling)";
  info.backend = Backend::embree;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::scene_geometry};
  info.params = {
      int_param({.name = "rays",
                 .def = 16,
                 .min = 1,
                 .max = 65536,
                 .spacing = Spacing::log,
                 .unit = "rays",
                 .meaning =
                     "Nobs: obscurance rays per pixel, cosine-distributed (§4.1; Fig. 6 uses 16)"}),
      real_param({.name = "dmax",
                  .def = 1.0,
                  .min = 1e-6,
                  .max = 1e6,
                  .spacing = Spacing::log,
                  .unit = "scene units",
                  .meaning = "maximum distance of interaction: rho = 1 beyond it (eq. 2; Fig. 7)"}),
      choice_param(
          {.name = "rho",
           .def = "sqrt",
           .choices = {"exp", "sqrt", "constant", "power"},
           .meaning =
               "obscurance function (§3): sqrt = sqrt(d/dmax), exp = (1-e^(-4d/dmax))/(1-e^-4), "
               "constant = 0 within dmax (AO), power = (d/dmax)^rho_k (CONTRACT §3 power:K)"}),
      power_exponent_param(
          "rho_k",
          "the exponent K of rho = power, rho(x) = x^K (1 = linear, 0.5 = sqrt); unused otherwise"),
      choice_param(
          {.name = "sampling",
           .def = "systematic",
           .choices = {"random", "systematic"},
           .meaning = "random, or systematic: an n1 x n2 grid with one random offset (§4.2)"}),
      seed_param("random seed (the references use 1, so the two never share samples)"),
  };
  info.definition_doc =
      "cosine weighting, dmax = dmax, falloff = rho (sqrt -> sqrt, exp -> exp, constant -> none, "
      "power -> power:rho_k): "
      "ray value rho(d/dmax) for d < dmax, else 1 (AoDefinition::ray_value). obscurance.R/G/B: "
      "mean over rays of R(Q) rho(d/dmax) for a hit Q within dmax (R(Q) = the hit object's "
      "albedo), else R_ave = area-weighted mean albedo of the scene (eq. 3); below-surface "
      "directions are worth 0";
  info.definition = [](const ParamSet& p) {
    const AoDefinition d = definition_of(obscurance_settings_of(p));
    validate_definition(d);
    return d;
  };
  info.create = [](const ParamSet& p) { return std::make_unique<ObscurancesEstimator>(p); };
  return info;
}

}  // namespace aoeval
