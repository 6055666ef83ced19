// The APNG writer: the chunk sequence a decoder needs (acTL with the frame count, fcTL before
// every frame, sequence numbers 0, 1, 2, ... over fcTL and fdAT, frame 0 in IDAT, every CRC
// right), frame 0 as a plain PNG reader sees it equal to the frame written, bit for bit, and
// frames of different sizes refused. (Chromium decoding every frame: the browser test,
// reports/browser_test/check_video.js.)
#include "reports/apng.h"

#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "base/testing/test_temp_dir.h"

namespace aoeval {
namespace {

OIIO::ImageBuf grey_ramp(int w, int h, int shift) {
  OIIO::ImageBuf b(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = static_cast<float>((x * 7 + y * 3 + shift) % 256) / 255.0f;
      const float px[3] = {v, v, v};
      b.setpixel(x, y, px);
    }
  return b;
}

uint32_t be32(const std::vector<uint8_t>& f, size_t at) {
  return (uint32_t{f[at]} << 24) | (uint32_t{f[at + 1]} << 16) | (uint32_t{f[at + 2]} << 8) |
         uint32_t{f[at + 3]};
}

TEST(Apng, ChunksInOrderAndFrameZeroExact) {
  const auto dir = testutil::test_temp_dir("apng");
  const std::string path = (dir / "video.png").string();
  std::vector<OIIO::ImageBuf> frames;
  for (int k = 0; k < 3; ++k) frames.push_back(grey_ramp(37, 21, 40 * k));
  write_apng(frames, 12.0, path);

  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> f((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
  ASSERT_GT(f.size(), 8u);
  std::vector<std::string> types;
  std::vector<uint32_t> sequence;
  for (size_t at = 8; at + 12 <= f.size();) {
    const uint32_t length = be32(f, at);
    const std::string type(f.begin() + static_cast<long>(at) + 4,
                           f.begin() + static_cast<long>(at) + 8);
    types.push_back(type);
    if (type == "acTL") {
      EXPECT_EQ(be32(f, at + 8), 3u) << "frame count";
    }
    if (type == "fcTL" || type == "fdAT") sequence.push_back(be32(f, at + 8));
    if (type == "fcTL") {
      EXPECT_EQ(be32(f, at + 12), 37u);
      EXPECT_EQ(be32(f, at + 16), 21u);
      EXPECT_EQ(f[at + 30] * 256 + f[at + 31], 12) << "delay 1/12 s";
    }
    at += 12 + length;
  }
  ASSERT_GE(types.size(), 8u);
  EXPECT_EQ(types.front(), "IHDR");
  EXPECT_EQ(types[1], "acTL");
  EXPECT_EQ(types.back(), "IEND");
  EXPECT_EQ(std::count(types.begin(), types.end(), "fcTL"), 3);
  EXPECT_EQ(std::count(types.begin(), types.end(), "fdAT"), 2);
  const auto first_fctl = std::find(types.begin(), types.end(), "fcTL");
  EXPECT_EQ(*(first_fctl + 1), "IDAT");  // frame 0 is the default image
  for (size_t i = 0; i < sequence.size(); ++i) EXPECT_EQ(sequence[i], i);

  // A plain PNG reader (OpenImageIO's) checks every CRC and sees frame 0, exactly: grey frames
  // as one grey channel.
  OIIO::ImageBuf back(path);
  ASSERT_TRUE(back.read(0, 0, true, OIIO::TypeDesc::UINT8)) << back.geterror();
  EXPECT_EQ(back.spec().width, 37);
  EXPECT_EQ(back.nchannels(), 1);
  const auto diff = OIIO::ImageBufAlgo::compare(
      back, OIIO::ImageBufAlgo::channels(frames[0], 1, {0}), 0.0f, 0.0f);
  EXPECT_EQ(diff.maxerror, 0.0);

  frames.push_back(grey_ramp(38, 21, 0));
  EXPECT_THROW(write_apng(frames, 12.0, (dir / "bad.png").string()), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.png"));
}

// One coloured pixel in one frame keeps every frame RGB, exactly.
TEST(Apng, AColouredPixelKeepsTheFramesRgb) {
  const auto dir = testutil::test_temp_dir("apng_rgb");
  const std::string path = (dir / "video.png").string();
  std::vector<OIIO::ImageBuf> frames = {grey_ramp(9, 7, 0), grey_ramp(9, 7, 5)};
  const float red[3] = {1.0f, 0.0f, 0.0f};
  frames[1].setpixel(4, 3, red);
  write_apng(frames, 10.0, path);
  OIIO::ImageBuf back(path);
  ASSERT_TRUE(back.read(0, 0, true, OIIO::TypeDesc::UINT8)) << back.geterror();
  EXPECT_EQ(back.nchannels(), 3);
  EXPECT_EQ(OIIO::ImageBufAlgo::compare(back, frames[0], 0.0f, 0.0f).maxerror, 0.0);
}

}  // namespace
}  // namespace aoeval
