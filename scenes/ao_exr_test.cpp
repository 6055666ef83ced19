// The one reader of AO EXRs (ao_exr.h): a covered pixel's AO_stderr must be a standard error of
// values in [0, 1] (finite, >= 0, <= 0.5). A NaN, infinite, negative or huge one made a damaged
// reference score as perfect (rmse_excess = sqrt(max(0, rmse^2 - stderr^2)) = 0).
#include "scenes/ao_exr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/exr_io.h"

namespace aoeval {
namespace {

// A 3 x 2 reference: AO 0.5, A = 1 except pixel (0, 0), AO_stderr 0.01 except `value` at (2, 1)
// and NaN at the uncovered (0, 0), which no one reads.
std::string write_reference(float value) {
  const std::string path = (testutil::test_temp_dir("ao_exr") / "ref.exr").string();
  OIIO::ImageSpec spec(3, 2, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "AO_stderr", "A"};
  OIIO::ImageBuf image(spec);
  auto* px = static_cast<float*>(image.localpixels());
  for (int k = 0; k < 6; ++k) {
    px[3 * k] = 0.5f;
    px[3 * k + 1] = k == 0 ? std::nanf("") : k == 5 ? value : 0.01f;
    px[3 * k + 2] = k == 0 ? 0.0f : 1.0f;
  }
  write_exr(path, image, {});
  return path;
}

TEST(AoExr, AStderrOutsideZeroToOneHalfIsRefusedNamingFileAndPixel) {
  const float inf = std::numeric_limits<float>::infinity();
  for (const float bad : {std::nanf(""), inf, -inf, -1.0f, 100.0f, 0.6f}) {
    SCOPED_TRACE(bad);
    const std::string path = write_reference(bad);
    for (const bool need : {false, true}) {
      try {
        read_ao_exr(path, need);
        ADD_FAILURE() << "read";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": AO_stderr value ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find(" at pixel (2, 1) is outside [0, 0.5]"),
                  std::string::npos)
            << e.what();
      }
    }
  }
  for (const float good : {0.0f, 0.25f, 0.5f}) {
    const AoExr f = read_ao_exr(write_reference(good), true);
    EXPECT_EQ(f.stderr_ao[5], good);
  }
}

}  // namespace
}  // namespace aoeval
