#include "reference_cache.h"

#include <filesystem>

#include "gbuffer.h"

namespace aoeval {

namespace {
uint64_t fnv1a(const std::string& s) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}
}  // namespace

std::string reference_cache_key(const Scene& scene, const Camera& camera,
                                const ReferenceSettings& settings) {
  const nlohmann::json key = {{"scene", hash_hex(scene.content_hash())},
                              {"camera", nlohmann::json::parse(camera_to_json(camera))},
                              {"settings", reference_params(settings)},
                              {"generator", kReferenceGeneratorVersion}};
  const std::string text = key.dump();
  // Two independent 64-bit hashes of the canonical text (sorted keys): 128 bits, no collisions
  // in practice.
  return hash_hex(fnv1a(text)) + hash_hex(fnv1a("aoeval-salt:" + text));
}

std::string reference_cache_path(const std::string& key) {
  return (std::filesystem::path(data_cache_dir()) / "references" / (key + ".exr")).string();
}

Attributes reference_attributes(const Scene& scene, const View& view, const Camera& camera,
                                const ReferenceSettings& settings) {
  Attributes a = gbuffer_attributes(scene, view, camera);
  a.emplace_back("aoeval:definition", settings.definition.to_json().dump());
  a.emplace_back("aoeval:spp", std::to_string(settings.spp));
  a.emplace_back("aoeval:sampler", sampler_name(settings.sampler));
  a.emplace_back("aoeval:seed", std::to_string(settings.seed));
  a.emplace_back("aoeval:estimator", "reference");
  a.emplace_back("aoeval:params", reference_params(settings).dump());
  return a;
}

}  // namespace aoeval
