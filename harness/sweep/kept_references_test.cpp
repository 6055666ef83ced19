// The kept files' precision (kept_references.h): every value rounded to the nearest float16, still
// float32, within 2^-11 of it relative (4.9e-4 absolute in [0, 1]), idempotent, and a value
// beyond float16's range kept as it is; written PXR24 compressed and read back bit for bit (zip
// when a value is beyond float16's range); and the sweep spec's adaptive timing keys.
#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <utility>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "harness/sweep/kept_references.h"
#include "harness/sweep/sweep_spec.h"
#include "scenes/pxr24_level.h"

namespace aoeval {
namespace {

// The compression `path` was written with, read from its header (an ImageBuf's spec may come from
// OIIO's shared image cache, which remembers a file written earlier at the same path).
std::string compression_of(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  return in ? std::string(in->spec().get_string_attribute("compression")) : "unreadable";
}

TEST(KeptReferences, HalfPrecisionIsWithinFloat16sStepAndIdempotent) {
  OIIO::ImageSpec spec(64, 4, 2, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf image(spec);
  double worst = 0.0;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 64; ++x) {
      const float v[2] = {static_cast<float>(std::fmod(0.0123457 * (1 + x + 64 * y), 1.0)),
                          y == 3 ? 1.0e6f : 1e-3f * static_cast<float>(x)};
      image.setpixel(x, y, v);
    }
  const OIIO::ImageBuf rounded = at_half_precision(image);
  ASSERT_EQ(rounded.spec().format, OIIO::TypeDesc::FLOAT);
  bool changed = false;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 2; ++c) {
        const float before = image.getchannel(x, y, 0, c), after = rounded.getchannel(x, y, 0, c);
        if (before == 1.0e6f) {
          EXPECT_EQ(after, before);  // beyond float16's range: kept
          continue;
        }
        changed = changed || after != before;
        EXPECT_LE(std::fabs(after - before), std::ldexp(std::fabs(before), -11) + 3e-8f);
        if (before <= 1.0f) worst = std::max(worst, std::fabs(double(after) - before));
      }
  EXPECT_TRUE(changed);
  EXPECT_LE(worst, 4.9e-4);
  const OIIO::ImageBuf again = at_half_precision(rounded);
  for (int x = 0; x < 64; ++x)
    EXPECT_EQ(again.getchannel(x, 1, 0, 0), rounded.getchannel(x, 1, 0, 0));
}

// A noisy image at float16 precision, written compact and read back: every bit kept, PXR24 chosen;
// one value beyond float16's range: zip, and that value kept exactly too.
TEST(KeptReferences, CompactFilesReadBackBitForBit) {
  OIIO::ImageSpec spec(97, 31, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"A", "AO", "bent.Y"};
  OIIO::ImageBuf image(spec);
  uint32_t state = 12345;
  for (int y = 0; y < 31; ++y)
    for (int x = 0; x < 97; ++x) {
      state = state * 1664525u + 1013904223u;
      const float u = static_cast<float>(state >> 8) / 16777216.0f;
      const float v[3] = {1.0f, u, 1e-3f * u * u};  // subnormal-to-normal float16 range
      image.setpixel(x, y, v);
    }
  const std::string dir = testutil::test_temp_dir("kept_compact").string();
  for (const bool beyond : {false, true}) {
    if (beyond) image.setpixel(5, 7, std::vector<float>{1.0f, 1.0e6f + 1.0f, 0.0f}.data());
    const std::string path = dir + (beyond ? "/beyond.exr" : "/half.exr");
    write_half_precision_exr(path, image, {});
    const OIIO::ImageBuf rounded = at_kept_precision(image);
    EXPECT_EQ(pxr24_keeps_bits(rounded), !beyond);
    OIIO::ImageBuf back(path);
    ASSERT_TRUE(back.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    EXPECT_EQ(compression_of(path), beyond ? "zip" : "pxr24");
    int differing = 0;
    for (int y = 0; y < 31; ++y)
      for (int x = 0; x < 97; ++x)
        for (int c = 0; c < 3; ++c) {
          const float a = back.getchannel(x, y, 0, c), b = rounded.getchannel(x, y, 0, c);
          differing += std::memcmp(&a, &b, sizeof a) != 0;
        }
    EXPECT_EQ(differing, 0);
  }
}

// OpenEXR's PXR24 writes deflate through this executable's compress() (scenes/pxr24_level.h), at
// kPxr24ZlibLevel: each PXR24 file calls it, a ZIP file (compress2) does not, and the file reads
// back bit for bit (CompactFilesReadBackBitForBit). Fails if the link stops exporting compress():
// libOpenEXR would then call libz's, at level 6.
TEST(KeptReferences, Pxr24DeflatesThroughTheExecutablesCompress) {
  OIIO::ImageSpec spec(64, 40, 2, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"A", "AO"};
  OIIO::ImageBuf image(spec);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 64; ++x) {
      const float v[2] = {1.0f, static_cast<float>((x * 7 + y * 13) % 29) / 29.0f};
      image.setpixel(x, y, v);
    }
  const std::string dir = testutil::test_temp_dir("kept_pxr24_level").string();
  const uint64_t before = pxr24_deflate_count();
  write_half_precision_exr(dir + "/frame.exr", image, {});
  ASSERT_EQ(compression_of(dir + "/frame.exr"), "pxr24");
  const uint64_t after_pxr24 = pxr24_deflate_count();
  EXPECT_GT(after_pxr24, before);
  write_exr(dir + "/zip.exr", image, {}, "zip");
  EXPECT_EQ(pxr24_deflate_count(), after_pxr24);
}

// A run's still estimate: AO, A and AO_stderr at PXR24's precision (A exact, AO within 2^-17),
// the bent normal in steps of 1/512, another extra (obscurance.R) of 1/2048, the header kept,
// PXR24, and a smaller file.
TEST(KeptReferences, EstimateExtrasRoundedAndAoAtPxr24Precision) {
  OIIO::ImageSpec spec(64, 48, 6, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"A", "AO", "AO_stderr", "bent.X", "bent.Y", "obscurance.R"};
  OIIO::ImageBuf image(spec);
  uint32_t state = 777;
  const auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / 16777216.0f;
  };
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const float v[6] = {1.0f, next(), 0.01f * next(), next() - 0.5f, next(), next() - 0.5f};
      image.setpixel(x, y, v);
    }
  const std::string path = testutil::test_temp_dir("kept_extras").string() + "/estimate.exr";
  write_exr(path, image, {{"aoeval:estimator", "gtao"}});
  const auto before = std::filesystem::file_size(path);
  compact_estimate_extras(path);
  EXPECT_LT(std::filesystem::file_size(path), before);
  OIIO::ImageBuf back(path);
  ASSERT_TRUE(back.read(0, 0, true, OIIO::TypeDesc::FLOAT));
  EXPECT_EQ(back.spec().get_string_attribute("aoeval:estimator"), "gtao");
  EXPECT_EQ(compression_of(path), "pxr24");
  int exact_differ = 0, extras_not_rounded = 0, ao_moved = 0;
  double worst_ao = 0.0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 6; ++c) {
        const float got = back.getchannel(x, y, 0, c);
        const float original = image.getchannel(x, y, 0, c);
        const float want = c < 3   ? at_pxr24_precision(original)
                           : c < 5 ? at_fixed_step(original, 512)  // bent.X, bent.Y
                                   : at_fixed_step(original, 2048);
        (c < 3 ? exact_differ : extras_not_rounded) += std::memcmp(&got, &want, sizeof got) != 0;
        if (c == 1) {
          worst_ao = std::max(worst_ao, std::fabs(double(got) - original));
          ao_moved += got != original;
        }
      }
  EXPECT_EQ(exact_differ, 0);
  EXPECT_EQ(extras_not_rounded, 0);
  EXPECT_GT(ao_moved, 0);                     // PXR24 rounds a full float32
  EXPECT_LE(worst_ao, std::ldexp(1.0, -17));  // within 7.7e-6 in [0, 1], the README's bound
  EXPECT_EQ(at_pxr24_precision(1.0f), 1.0f);
  EXPECT_EQ(at_pxr24_precision(0.0f), 0.0f);
  EXPECT_TRUE(std::isnan(at_pxr24_precision(std::nanf(""))));
  // Written once from memory (a suite run's session, write_compact_estimate): the same values
  // and header as written plain and then compacted.
  const std::string once = path + ".once.exr";
  write_compact_estimate(once, image, {{"aoeval:estimator", "gtao"}});
  OIIO::ImageBuf direct(once);
  ASSERT_TRUE(direct.read(0, 0, true, OIIO::TypeDesc::FLOAT));
  EXPECT_EQ(direct.spec().get_string_attribute("aoeval:estimator"), "gtao");
  EXPECT_EQ(compression_of(once), "pxr24");
  int differ = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 6; ++c) {
        const float a = direct.getchannel(x, y, 0, c), b = back.getchannel(x, y, 0, c);
        differ += std::memcmp(&a, &b, sizeof a) != 0;
      }
  EXPECT_EQ(differ, 0);
}

// The kept precision, channel by channel: AO_stderr at 3 significant bits (a float16: one of the
// two such values around it), bent.X/Y/Z in steps of 1/512, AO at float16; a bent channel with a
// value beyond +-2 at float16 too.
TEST(KeptReferences, KeptPrecisionIsRelativeForStderrFixedForBentFloat16Otherwise) {
  OIIO::ImageSpec spec(50, 20, 4, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "AO_stderr", "bent.X", "bent.Y"};
  OIIO::ImageBuf image(spec);
  uint32_t state = 4242;
  for (OIIO::ImageBuf::Iterator<float> it(image); !it.done(); ++it) {
    for (int c = 0; c < 4; ++c) {
      state = state * 1664525u + 1013904223u;
      const float u = static_cast<float>(state >> 8) / 16777216.0f;
      it[c] = c == 1 ? 0.06f * u * u * u : u;  // stderr over 4 decades, 0 to 0.06
    }
  }
  image.setpixel(3, 3, std::vector<float>{0.5f, 0.01f, 0.2f, 3.0f}.data());  // bent.Y beyond 2
  image.setpixel(4, 3, std::vector<float>{0.5f, 1e-6f, 0.2f, 0.2f}.data());  // below normal half
  image.setpixel(5, 3, std::vector<float>{0.5f, 0.01171875f, 0.2f, 0.2f}.data());  // 3 bits: kept
  const OIIO::ImageBuf kept = at_kept_precision(image), half_rounded = at_half_precision(image);
  double worst[4] = {0, 0, 0, 0}, worst_relative = 0.0;
  int wrong = 0, not_half = 0, not_a_neighbour = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 50; ++x)
      for (int c = 0; c < 4; ++c) {
        const float v = image.getchannel(x, y, 0, c), got = kept.getchannel(x, y, 0, c);
        const uint64_t pixel = static_cast<uint64_t>(y) * 50 + static_cast<uint64_t>(x);
        const float want = c == 1   ? at_significant_bits(v, 3, kept_dither(pixel, c))
                           : c == 2 ? at_fixed_step(v, 512)
                                    : half_rounded.getchannel(x, y, 0, c);  // AO; bent.Y (a 3)
        wrong += std::memcmp(&got, &want, sizeof got) != 0;
        worst[c] = std::max(worst[c], std::fabs(double(got) - v));
        if (c == 1 && v >= 0x1p-14f) {
          worst_relative = std::max(worst_relative, std::fabs(got / v - 1.0));
          // got is the 3-bit value at or below v, or the next one up
          int e = 0;
          const double eighths = std::floor(std::ldexp(std::frexp(double(v), &e), 3));
          const double lo = std::ldexp(eighths, e - 3);
          not_a_neighbour += got != lo && got != lo + std::ldexp(1.0, e - 3);
        }
        not_half += static_cast<float>(half(got)) != got;
      }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(not_half, 0);  // every kept value is a float16: the viewer's equals the file's
  EXPECT_EQ(not_a_neighbour, 0);
  EXPECT_LE(worst_relative, 0.25 + 1e-7);
  EXPECT_GT(worst_relative, 1.0 / 16);                  // coarser than float16: it did round
  EXPECT_EQ(kept.getchannel(5, 3, 0, 1), 0.01171875f);  // 0.75 x 2^-6: already 3 bits
  EXPECT_LE(worst[2], 0.5 / 512 + 1e-9);
  EXPECT_GT(worst[2], 0.25 / 512);
  EXPECT_EQ(kept.getchannel(4, 3, 0, 1), static_cast<float>(half(1e-6f)));
  EXPECT_TRUE(pxr24_keeps_bits(kept));
  EXPECT_EQ(kept_rounding("AO").kind, KeptRounding::half);
  EXPECT_EQ(kept_rounding("bent_stderr").kind, KeptRounding::significant);
  EXPECT_EQ(at_significant_bits(-0.75f, 3, 0.5), -0.75f);
  EXPECT_EQ(at_significant_bits(0.0f, 3, 0.5), 0.0f);
  EXPECT_TRUE(std::isnan(at_significant_bits(std::nanf(""), 3, 0.5)));
}

// What the noise removals read, mean(stderr^2), is unbiased after the kept rounding: an image of
// one stderr value v between two 3-bit values lo < v < hi keeps lo or hi with P(hi) = p = (v^2 -
// lo^2) / (hi^2 - lo^2), so the mean of N kept squares has standard deviation sqrt(p (1 - p) / N)
// (hi^2 - lo^2); it lies within 4 of them of v^2 (rounding to the nearest, hi here, is 19 of them
// off). Two images of the same values keep the same bits.
TEST(KeptReferences, KeptStderrKeepsTheMeanSquareUnbiased) {
  const int w = 50, h = 20;
  OIIO::ImageSpec spec(w, h, 2, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "AO_stderr"};
  for (const float v : {0.0221f, 0.0031f, 0.047f}) {
    SCOPED_TRACE(v);
    OIIO::ImageBuf image(spec);
    for (OIIO::ImageBuf::Iterator<float> it(image); !it.done(); ++it) it[0] = 0.5f, it[1] = v;
    const OIIO::ImageBuf kept = at_kept_precision(image), again = at_kept_precision(image);
    int e = 0;
    const double eighths = std::floor(std::ldexp(std::frexp(double(v), &e), 3));  // 4..7
    const double lo = std::ldexp(eighths, e - 3);
    const double hi = lo + std::ldexp(1.0, e - 3);
    const double p = (double(v) * v - lo * lo) / (hi * hi - lo * lo);
    double sum = 0.0;
    int differ = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double k = kept.getchannel(x, y, 0, 1);
        sum += k * k;
        differ += kept.getchannel(x, y, 0, 1) != again.getchannel(x, y, 0, 1);
      }
    const double n = w * h, sd = std::sqrt(p * (1.0 - p) / n) * (hi * hi - lo * lo);
    EXPECT_NEAR(sum / n, double(v) * v, 4.0 * sd);
    EXPECT_EQ(differ, 0);
  }
}

// A sequence point's maps.exr: flicker and lag at multiples of 1/4096 (the viewer's fixed point),
// A exact, PXR24; a NaN in a channel keeps that channel at float16 and the file zip.
TEST(KeptReferences, CompactMapsAreFixedPointAndPxr24) {
  OIIO::ImageSpec spec(40, 30, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"flicker", "lag", "A"};
  OIIO::ImageBuf image(spec);
  uint32_t state = 99;
  for (OIIO::ImageBuf::Iterator<float> it(image); !it.done(); ++it)
    for (int c = 0; c < 3; ++c) {
      state = state * 1664525u + 1013904223u;
      const float u = static_cast<float>(state >> 8) / 16777216.0f;
      it[c] = c == 2 ? (u < 0.8f ? 1.0f : 0.0f) : 0.3f * u;
    }
  const std::string dir = testutil::test_temp_dir("kept_maps").string();
  write_compact_maps(dir + "/maps.exr", image, {{"aoeval:run_name", "p"}});
  EXPECT_EQ(compression_of(dir + "/maps.exr"), "pxr24");
  OIIO::ImageBuf back(dir + "/maps.exr");
  ASSERT_TRUE(back.read(0, 0, true, OIIO::TypeDesc::FLOAT));
  EXPECT_EQ(back.spec().get_string_attribute("aoeval:run_name"), "p");
  int wrong = 0;
  double worst = 0.0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 3; ++c) {
        const int in_file = back.spec().channelindex(image.spec().channelnames[c]);  // sorted
        const float v = image.getchannel(x, y, 0, c), got = back.getchannel(x, y, 0, in_file);
        const float want = at_fixed_step(v, 4096);
        wrong += std::memcmp(&got, &want, sizeof got) != 0;
        worst = std::max(worst, std::fabs(double(got) - v));
      }
  EXPECT_EQ(wrong, 0);
  EXPECT_LE(worst, 0.5 / 4096 + 1e-9);
  image.setpixel(1, 1, std::vector<float>{std::nanf(""), 0.1f, 1.0f}.data());
  write_compact_maps(dir + "/nan.exr", image, {});
  EXPECT_EQ(compression_of(dir + "/nan.exr"), "zip");
}

TEST(KeptReferences, AdaptiveTimingKeysParse) {
  nlohmann::json j = {{"name", "t"},
                      {"scenes", {"bunny"}},
                      {"runs", {{{"estimator", "constant"}}}},
                      {"timing", {{"repetitions", 3}, {"max_repetitions", 15}}}};
  const SweepSpec s = parse_sweep_spec(j, "spec.json");
  EXPECT_EQ(s.timing.repetitions, 3);
  EXPECT_EQ(s.timing.max_repetitions, 15);
  EXPECT_DOUBLE_EQ(s.timing.median_ci, 0.05);
  j["timing"] = {{"repetitions", 5}};
  EXPECT_EQ(parse_sweep_spec(j, "spec.json").timing.max_repetitions, 5);  // fixed, as before
  j["timing"] = {{"repetitions", 5}, {"max_repetitions", 4}};
  EXPECT_THROW(parse_sweep_spec(j, "spec.json"), InputError);  // the maximum below the least
}

}  // namespace
}  // namespace aoeval
