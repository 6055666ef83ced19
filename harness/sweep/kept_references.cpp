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

namespace {

// `image`'s values as float32, interleaved (channels innermost), and an image of `like`'s spec
// (its metadata included) holding `values`: the rounding below runs over plain arrays instead of
// OIIO's pixel iterators (issue 42: the kept sequence frames' rounding and checks cost several
// times their values' arithmetic through the iterators).
std::vector<float> values_of(const OIIO::ImageBuf& image) {
  std::vector<float> values(image.spec().image_pixels() * image.nchannels());
  if (!image.get_pixels(image.roi(), OIIO::TypeDesc::FLOAT, values.data()))
    throw std::runtime_error("reading pixels: " + image.geterror());
  return values;
}

OIIO::ImageBuf image_of(const OIIO::ImageBuf& like, const std::vector<float>& values) {
  OIIO::ImageSpec spec = like.spec();
  spec.set_format(OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf out(spec);
  if (!out.set_pixels(out.roi(), OIIO::TypeDesc::FLOAT, values.data()))
    throw std::runtime_error("writing pixels: " + out.geterror());
  return out;
}

float at_half(float v) {
  return std::isfinite(v) && std::fabs(v) <= HALF_MAX ? static_cast<float>(half(v)) : v;
}

}  // namespace

OIIO::ImageBuf at_half_precision(const OIIO::ImageBuf& image) {
  std::vector<float> values = values_of(image);
  for (float& v : values) v = at_half(v);
  return image_of(image, values);
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
  std::vector<float> values = values_of(image);
  const size_t channels = static_cast<size_t>(image.nchannels());
  std::vector<KeptRounding> rounding(channels);
  for (size_t c = 0; c < channels; ++c) rounding[c] = rounding_of(image.spec().channelnames[c]);
  for (size_t i = 0; i < values.size(); ++i)
    if (!(std::fabs(values[i]) <= kKeptFixedRange))
      rounding[i % channels] = {KeptRounding::half, 0};
  for (size_t i = 0; i < values.size(); ++i) {
    const size_t c = i % channels;
    switch (rounding[c].kind) {
      case KeptRounding::fixed:
        values[i] = at_fixed_step(values[i], rounding[c].value);
        break;
      case KeptRounding::significant:  // the pixel's index, y * width + x, as the dither's key
        values[i] = at_significant_bits(values[i], rounding[c].value,
                                        kept_dither(i / channels, static_cast<int>(c)));
        break;
      case KeptRounding::half:
        values[i] = at_half(values[i]);
        break;
    }
  }
  return image_of(image, values);
}

OIIO::ImageBuf at_kept_precision(const OIIO::ImageBuf& image) {
  return rounded_by_channel(image, kept_rounding);
}

bool pxr24_keeps_bits(const OIIO::ImageBuf& image) {
  for (const float v : values_of(image)) {
    const float back = at_pxr24_precision(v);
    if (!std::isfinite(v) || std::memcmp(&v, &back, sizeof v) != 0) return false;
  }
  return true;
}

// `rounded` (already at the precision it is kept at) as a 32-bit float EXR: PXR24 where it keeps
// every value bit for bit, zip otherwise.
static void write_rounded_exr(const std::string& path, const OIIO::ImageBuf& rounded,
                              const Attributes& attributes) {
  write_exr(path, rounded, attributes, pxr24_keeps_bits(rounded) ? "pxr24" : "zip");
}

void write_half_precision_exr(const std::string& path, const OIIO::ImageBuf& image,
                              const Attributes& attributes) {
  write_rounded_exr(path, at_kept_precision(image), attributes);
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
  const std::vector<float> rounded =
      values_of(rounded_by_channel(image, [](const std::string& name) {
        const KeptRounding bent = kept_rounding(name);  // a bent normal as a kept reference's
        return bent.kind == KeptRounding::fixed ? bent : KeptRounding{KeptRounding::fixed, 2048};
      }));
  std::vector<float> values = values_of(image);
  const size_t channels = names.size();
  for (size_t i = 0; i < values.size(); ++i)
    if (!exact(names[i % channels])) values[i] = rounded[i];
  write_exr(path, image_of(image, values), attributes, "pxr24");
}

void write_compact_maps(const std::string& path, const OIIO::ImageBuf& maps,
                        const Attributes& attributes) {
  const OIIO::ImageBuf rounded = rounded_by_channel(maps, [](const std::string&) {
    return KeptRounding{KeptRounding::fixed, kKeptMapStep};  // A's 0 and 1 stay exact
  });
  write_rounded_exr(path, rounded, attributes);
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
      write_rounded_exr(temp, rounded, {{"aoeval:checksum", image_checksum(rounded)}});
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
