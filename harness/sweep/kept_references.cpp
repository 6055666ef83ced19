#include "harness/sweep/kept_references.h"

#include <Imath/half.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>

#include "base/text_files.h"
#include "harness/results/result_row.h"
#include "references/reference_cache.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

std::string frame_file_name(int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", frame);
  return name;
}

std::string KeptReferences::stem(EvaluationSession& session, const std::string& scene_name,
                                 const View& view, int w, int h,
                                 const AoDefinition& definition) const {
  const Scene& scene = session.scene(scene_name).scene;
  const ReferenceSpec& spec = session.reference_spec();
  return "references/" +
         file_stem_for(scene.name + "/" + view.name + "/" + std::to_string(w) + "x" +
                       std::to_string(h) + "/" + definition.label() +
                       "/spp:" + std::to_string(spec.spp) + "/" + sampler_name(spec.sampler) +
                       "/seed:" + std::to_string(spec.seed));
}

OIIO::ImageBuf only_channels(const OIIO::ImageBuf& image, const std::vector<std::string>& names,
                             const std::string& path) {
  std::vector<int> order;
  for (const auto& name : names) order.push_back(channel_index(image, name, path));
  OIIO::ImageBuf out;
  if (!OIIO::ImageBufAlgo::channels(out, image, static_cast<int>(order.size()), order.data()))
    throw std::runtime_error(path + ": " + out.geterror());
  return out;
}

OIIO::ImageBuf at_half_precision(const OIIO::ImageBuf& image) {
  OIIO::ImageBuf out;
  out.copy(image, OIIO::TypeDesc::FLOAT);
  const int channels = out.nchannels();
  for (OIIO::ImageBuf::Iterator<float> it(out); !it.done(); ++it)
    for (int c = 0; c < channels; ++c) {
      const float v = it[c];
      if (std::isfinite(v) && std::fabs(v) <= HALF_MAX) it[c] = static_cast<float>(half(v));
    }
  return out;
}

KeptRounding kept_rounding(const std::string& channel) {
  if (channel == "AO_stderr" || channel == "bent_stderr")
    return {KeptRounding::significant, kKeptStderrBits};
  if (channel == "bent.X" || channel == "bent.Y" || channel == "bent.Z")
    return {KeptRounding::fixed, kKeptBentStep};
  return {KeptRounding::half, 0};
}

float at_fixed_step(float v, int step) {
  return static_cast<float>(std::nearbyint(static_cast<double>(v) * step) / step);
}

float at_significant_bits(float v, int bits, double u) {
  if (!std::isfinite(v)) return v;
  if (std::fabs(v) < 0x1p-14f) return static_cast<float>(half(v));  // float16's normal range
  const double a = std::fabs(static_cast<double>(v));
  int exponent = 0;
  const double below = std::floor(std::ldexp(std::frexp(a, &exponent), bits));  // 2^(bits-1)..
  const double lo = std::ldexp(below, exponent - bits),
               hi = std::ldexp(below + 1.0, exponent - bits);
  // P(hi) so that E[kept^2] = v^2: p hi^2 + (1 - p) lo^2 = a^2.
  const double p_hi = (a * a - lo * lo) / (hi * hi - lo * lo);
  return static_cast<float>(std::copysign(u < p_hi ? hi : lo, static_cast<double>(v)));
}

double kept_dither(uint64_t pixel, int channel) {
  uint64_t z =
      pixel * 0x9e3779b97f4a7c15ull + static_cast<uint64_t>(channel) + 0x632be59bd9b4e019ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;  // splitmix64's finaliser
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1p-53;
}

// `image` with channel c rounded as `rounding_of(c's name)` says, when every value of c is finite
// and within +-kKeptFixedRange; else (or for KeptRounding::half) to float16.
static OIIO::ImageBuf rounded_by_channel(
    const OIIO::ImageBuf& image,
    const std::function<KeptRounding(const std::string&)>& rounding_of) {
  const OIIO::ImageBuf half_rounded = at_half_precision(image);
  OIIO::ImageBuf out;
  out.copy(half_rounded, OIIO::TypeDesc::FLOAT);
  const int channels = out.nchannels();
  std::vector<KeptRounding> rounding(channels);
  for (int c = 0; c < channels; ++c) rounding[c] = rounding_of(image.spec().channelnames[c]);
  for (OIIO::ImageBuf::ConstIterator<float> it(image); !it.done(); ++it)
    for (int c = 0; c < channels; ++c)
      if (!(std::fabs(it[c]) <= kKeptFixedRange)) rounding[c] = {KeptRounding::half, 0};
  OIIO::ImageBuf::ConstIterator<float> from(image);
  const auto width = static_cast<uint64_t>(image.spec().width);
  for (OIIO::ImageBuf::Iterator<float> it(out); !it.done(); ++it, ++from)
    for (int c = 0; c < channels; ++c) {
      if (rounding[c].kind == KeptRounding::fixed)
        it[c] = at_fixed_step(from[c], rounding[c].value);
      if (rounding[c].kind == KeptRounding::significant) {
        const uint64_t pixel =
            static_cast<uint64_t>(it.y()) * width + static_cast<uint64_t>(it.x());
        it[c] = at_significant_bits(from[c], rounding[c].value, kept_dither(pixel, c));
      }
    }
  return out;
}

OIIO::ImageBuf at_kept_precision(const OIIO::ImageBuf& image) {
  return rounded_by_channel(image, kept_rounding);
}

bool pxr24_keeps_bits(const OIIO::ImageBuf& image) {
  const int channels = image.nchannels();
  for (OIIO::ImageBuf::ConstIterator<float> it(image); !it.done(); ++it)
    for (int c = 0; c < channels; ++c) {
      const float v = it[c], back = at_pxr24_precision(v);
      if (!std::isfinite(v) || std::memcmp(&v, &back, sizeof v) != 0) return false;
    }
  return true;
}

void write_half_precision_exr(const std::string& path, const OIIO::ImageBuf& image,
                              const Attributes& attributes) {
  const OIIO::ImageBuf rounded = at_kept_precision(image);
  write_exr(path, rounded, attributes, pxr24_keeps_bits(rounded) ? "pxr24" : "zip");
}

float at_pxr24_precision(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const uint32_t sign = bits & 0x80000000u, e = bits & 0x7f800000u, m = bits & 0x007fffffu;
  uint32_t i;  // the 24-bit word, as OpenEXR's floatToFloat24 makes it
  if (e == 0x7f800000u) {
    i = (e >> 8) | (m >> 8) | (m && !(m >> 8) ? 1u : 0u);  // infinity; a NaN stays one
  } else {
    i = ((e | m) + (m & 0x80u)) >> 8;      // nearest, ties away from zero
    if (i >= 0x7f8000u) i = (e | m) >> 8;  // rounding would overflow: truncated
  }
  const uint32_t out = sign | (i << 8);
  float f;
  std::memcpy(&f, &out, sizeof f);
  return f;
}

void compact_estimate_extras(const std::string& path) {
  write_compact_estimate(path, read_image(path), {});  // the header the image was read with kept
}

void write_compact_estimate(const std::string& path, const OIIO::ImageBuf& image,
                            const Attributes& attributes) {
  const auto& names = image.spec().channelnames;
  const auto exact = [](const std::string& n) { return n == "AO" || n == "A" || n == "AO_stderr"; };
  const OIIO::ImageBuf rounded = rounded_by_channel(image, [](const std::string& name) {
    const KeptRounding bent = kept_rounding(name);  // a bent normal as a kept reference's
    return bent.kind == KeptRounding::fixed ? bent : KeptRounding{KeptRounding::fixed, 2048};
  });
  OIIO::ImageBuf out;
  out.copy(image, OIIO::TypeDesc::FLOAT);
  const int channels = out.nchannels();
  OIIO::ImageBuf::ConstIterator<float> from(rounded);
  for (OIIO::ImageBuf::Iterator<float> it(out); !it.done(); ++it, ++from)
    for (int c = 0; c < channels; ++c)
      if (!exact(names[c])) it[c] = from[c];
  write_exr(path, out, attributes, "pxr24");
}

void write_compact_maps(const std::string& path, const OIIO::ImageBuf& maps,
                        const Attributes& attributes) {
  const OIIO::ImageBuf rounded = rounded_by_channel(maps, [](const std::string&) {
    return KeptRounding{KeptRounding::fixed, kKeptMapStep};  // A's 0 and 1 stay exact
  });
  write_exr(path, rounded, attributes, pxr24_keeps_bits(rounded) ? "pxr24" : "zip");
}

void KeptReferences::copy(const std::string& from, const std::string& rel, bool frame) {
  const fs::path target = fs::path(out_) / rel;
  fs::create_directories(target.parent_path());
  const std::string temp = temporary_path_for(target.string());  // one naming: leftovers are found
  fs::remove(temp);
  // A sequence's still reference and its last frame's reference are one cache entry, kept with
  // different channels when compact: one kept file per (entry, channels).
  const bool fewer_channels = frame && !exact_;
  const auto [kept, fresh] = kept_from_.emplace(from + (fewer_channels ? "|AO" : ""), rel);
  std::error_code not_linked;
  if (!fresh) fs::create_hard_link(fs::path(out_) / kept->second, temp, not_linked);
  if (fresh || not_linked) {
    if (exact_) {
      fs::copy_file(from, temp, fs::copy_options::overwrite_existing);
    } else {
      OIIO::ImageBuf image = read_image(from);
      // A sequence frame's reference: what `aoeval compare --sequence` and the viewer read. The
      // bent normal and its stderr were 4 of its 7 channels and 60 % of its bytes, and no kept
      // frame estimate carries a bent normal to compare with them.
      if (fewer_channels) image = only_channels(image, {"A", "AO", "AO_stderr"}, from);
      // aoeval:checksum, copied from the cache entry, must describe the written pixels.
      const OIIO::ImageBuf rounded = at_kept_precision(image);
      write_half_precision_exr(temp, rounded, {{"aoeval:checksum", image_checksum(rounded)}});
    }
  }
  commit_temporary(temp, target.string());
}

std::string KeptReferences::keep(EvaluationSession& session, const std::string& scene_name,
                                 const View& view, int w, int h, const AoDefinition& definition) {
  const std::string rel = stem(session, scene_name, view, w, h, definition) + ".exr";
  if (!written_.insert(rel).second) return rel;
  session.reference(scene_name, view, w, h, definition);  // computes or reads the cache
  // The cache entry session.reference() used: for a sequence view that is its still frame (the
  // last one, whose estimate the row keeps), posed scene, camera and seed + k included.
  const int k = EvaluationSession::still_frame(view);
  copy(reference_cache_path(
           reference_cache_key(session.frame_scene(scene_name, view, k).content_hash,
                               session.gbuffer(scene_name, view, w, h).camera,
                               session.frame_settings(scene_name, view, k, definition))),
       rel, false);
  return rel;
}

std::string KeptReferences::keep_frame(EvaluationSession& session, const std::string& scene_name,
                                       const View& view, int w, int h,
                                       const AoDefinition& definition, int frame,
                                       const std::string& cache_path) {
  const std::string rel =
      stem(session, scene_name, view, w, h, definition) + "/" + frame_file_name(frame);
  if (written_.insert(rel).second) copy(cache_path, rel, true);
  return rel;
}

}  // namespace aoeval
