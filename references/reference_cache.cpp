#include "references/reference_cache.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

#include "base/errors.h"
#include "base/hash.h"
#include "scenes/ao_exr.h"
#include "scenes/exr_io.h"
#include "scenes/gbuffer.h"

namespace aoeval {

std::string reference_cache_key(const Scene& scene, const Camera& camera,
                                const ReferenceSettings& settings) {
  return reference_cache_key(scene.content_hash(), camera, settings);
}

std::string reference_cache_key(uint64_t scene_hash, const Camera& camera,
                                const ReferenceSettings& settings) {
  const nlohmann::json key = {{"scene", hash_hex(scene_hash)},
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
  return reference_attributes(scene, scene.content_hash(), view, camera, settings);
}

Attributes reference_attributes(const Scene& scene, uint64_t scene_hash, const View& view,
                                const Camera& camera, const ReferenceSettings& settings) {
  Attributes a = gbuffer_attributes(scene, scene_hash, view, camera);
  a.emplace_back("aoeval:definition", settings.definition.to_json().dump());
  a.emplace_back("aoeval:spp", std::to_string(settings.spp));
  a.emplace_back("aoeval:sampler", sampler_name(settings.sampler));
  a.emplace_back("aoeval:seed", std::to_string(settings.seed));
  a.emplace_back("aoeval:estimator", "reference");
  a.emplace_back("aoeval:params", reference_params(settings).dump());
  return a;
}

std::string image_checksum(const OIIO::ImageBuf& image) {
  // Channels in name order: OpenEXR stores them sorted by name, so the order in memory before a
  // write and after a read differ; the checksum must not.
  const OIIO::ImageSpec& spec = image.spec();
  std::vector<std::pair<std::string, int>> channels;
  for (int c = 0; c < spec.nchannels; ++c) channels.emplace_back(spec.channel_name(c), c);
  std::sort(channels.begin(), channels.end());
  Fnv1a hash;
  auto mix = [&hash](const std::string& bytes) { hash.text(bytes); };
  std::vector<float> plane(static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height));
  for (const auto& [name, index] : channels) {
    mix(name);
    OIIO::ROI roi = image.roi();
    roi.chbegin = index;
    roi.chend = index + 1;
    image.get_pixels(roi, OIIO::TypeDesc::FLOAT, plane.data());
    std::string bits(plane.size() * sizeof(float), '\0');
    std::memcpy(bits.data(), plane.data(), bits.size());
    mix(bits);
  }
  return hash_hex(hash.h);
}

void add_cache_attributes(Attributes& attributes, const std::string& key,
                          const OIIO::ImageBuf& image) {
  attributes.emplace_back("aoeval:cache_key", key);
  attributes.emplace_back("aoeval:checksum", image_checksum(image));
}

namespace {

// Why `image`, read from a cache entry, is not a valid entry for `key`, or "" when it is.
std::string image_entry_problem(const OIIO::ImageBuf& image, const std::string& key) {
  const std::string stored_key = string_attribute(image, "aoeval:cache_key");
  if (stored_key != key)
    return stored_key.empty() ? "carries no cache key (not written by this cache)"
                              : "carries the key of another entry (" + stored_key + ")";
  for (const char* channel : {"AO", "AO_stderr", "A"})
    if (image.spec().channelindex(channel) < 0) return std::string("has no channel ") + channel;
  const std::string stored = string_attribute(image, "aoeval:checksum");
  const std::string actual = image_checksum(image);
  if (stored != actual) return "pixel checksum " + actual + " does not match the stored " + stored;
  return "";
}

// The entry's image, or nullopt with `problem` set when it cannot be read (a truncated EXR).
std::optional<OIIO::ImageBuf> read_entry(const std::string& path, std::string& problem) {
  try {
    return read_image(path);
  } catch (const std::exception& e) {
    problem = std::string("unreadable (") + e.what() + ")";
    return std::nullopt;
  }
}

void report_and_remove(const std::string& path, const std::string& problem) {
  std::fprintf(stderr, "reference cache: %s: %s; recomputing\n", path.c_str(), problem.c_str());
  std::error_code ec;
  std::filesystem::remove(path, ec);
}

}  // namespace

std::string cache_entry_problem(const std::string& path, const std::string& key) {
  std::string problem;
  const std::optional<OIIO::ImageBuf> image = read_entry(path, problem);
  return image ? image_entry_problem(*image, key) : problem;
}

bool usable_cache_entry(const std::string& path, const std::string& key) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return false;
  const std::string problem = cache_entry_problem(path, key);
  if (problem.empty()) return true;
  report_and_remove(path, problem);
  return false;
}

std::optional<ReferenceImage> read_usable_cache_entry(const std::string& path,
                                                      const std::string& key) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  std::string problem;
  const std::optional<OIIO::ImageBuf> image = read_entry(path, problem);
  if (image) problem = image_entry_problem(*image, key);
  if (problem.empty()) {
    try {
      return reference_image_from(ao_exr_from_image(*image, path, /*need_stderr=*/true));
    } catch (const std::exception& e) {
      problem = e.what();
    }
  }
  report_and_remove(path, problem);
  return std::nullopt;
}

}  // namespace aoeval
