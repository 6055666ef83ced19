#include "references/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>

#include "base/errors.h"
#include "scenes/ao_exr.h"

namespace aoeval {

OIIO::ImageBuf reference_to_image(const ReferenceImage& r, bool with_spp) {
  std::vector<std::string> names = {"AO",     "AO_stderr", "bent.X",     "bent.Y",
                                    "bent.Z", "A",         "bent_stderr"};
  if (with_spp) names.push_back("spp");
  OIIO::ImageSpec spec(r.width, r.height, static_cast<int>(names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  OIIO::ImageBuf image(spec);
  auto* px = static_cast<float*>(image.localpixels());
  const size_t nc = names.size();
  for (size_t k = 0; k < r.ao.size(); ++k) {
    float* o = px + k * nc;
    o[0] = r.ao[k];
    o[1] = r.stderr_ao[k];
    o[2] = r.bent[k].x;
    o[3] = r.bent[k].y;
    o[4] = r.bent[k].z;
    o[5] = r.coverage[k];
    o[6] = r.bent_stderr.empty() ? 0.0f : r.bent_stderr[k];
    if (with_spp) o[7] = r.spp[k];
  }
  return image;
}

nlohmann::json reference_params(const ReferenceSettings& s) {
  nlohmann::json j = {{"spp", s.spp},
                      {"definition", s.definition.to_json()},
                      {"sampler", sampler_name(s.sampler)},
                      {"seed", s.seed},
                      {"normal", s.normal == NormalMode::shading ? "shading" : "geometric"},
                      {"replicates", replicate_count(s.sampler, s.spp)}};
  if (s.target_stderr > 0.0) {
    j["target_stderr"] = s.target_stderr;
    j["max_spp"] = s.max_spp;
  }
  return j;
}

void parse_reference_options(ReferenceSettings& s, const std::string& weighting,
                             const std::string& dmax, const std::string& falloff,
                             const std::string& sampler, const std::string& normal) {
  s.definition.weighting = parse_weighting(weighting);
  s.definition.dmax = parse_dmax(dmax);
  s.definition.falloff = parse_falloff(falloff);
  validate_definition(s.definition);
  s.sampler = parse_sampler(sampler);
  if (normal == "shading")
    s.normal = NormalMode::shading;
  else if (normal == "geometric")
    s.normal = NormalMode::geometric;
  else
    throw InputError("--normal: '" + normal + "' is not one of: shading, geometric");
}

}  // namespace aoeval

namespace aoeval {

ReferenceImage read_reference_image(const std::string& path) {
  return reference_image_from(read_ao_exr(path, /*need_stderr=*/true));
}

ReferenceImage reference_image_from(AoExr f) {
  ReferenceImage r;
  r.width = f.width;
  r.height = f.height;
  const size_t n = f.ao.size();
  r.ao = std::move(f.ao);
  r.stderr_ao = std::move(f.stderr_ao);
  r.coverage = std::move(f.coverage);
  r.bent = f.bent.empty() ? std::vector<glm::vec3>(n, glm::vec3(0.0f)) : std::move(f.bent);
  r.spp = f.spp.empty() ? std::vector<float>(n, 0.0f) : std::move(f.spp);
  r.bent_stderr = std::move(f.bent_stderr);
  return r;
}

}  // namespace aoeval
