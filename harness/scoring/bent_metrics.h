// Bent-normal metrics (CONTRACT §4): where an estimate carries bent.X/Y/Z, its bent normal is
// compared with the reference's over the compared pixels (the AO metrics' mask) where both bent
// normals are non-zero. Keys, angles in degrees between the two unit vectors (in double):
//   bent_pixels        the number of such pixels
//   bent_angle_mean    mean angle
//   bent_angle_p95     95th percentile of the angle by nearest rank (k = ceil(0.95 n), 1-based)
//   bent_ref_stderr    sqrt(mean ref_bent_stderr^2): the rms angular noise of the reference's
//                      bent normal (references/reference.h, bent_stderr), 0 when the reference
//                      does not carry it
//   bent_angle_excess  sqrt(max(0, mean angle^2 - mean ref_bent_stderr^2)): the rms angle with the
//                      reference's noise removed, as rmse_excess does for AO. A small angular
//                      error e of the estimate and the reference's independent error r (rms
//                      bent_stderr) give angle^2 = |e - r|^2 on average |e|^2 + |r|^2.
// The keys are absent (blank in CSV, missing in JSON) for estimates without bent normals.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

namespace aoeval {

struct BentMetrics {
  size_t pixels;
  double angle_mean, angle_p95, ref_stderr, angle_excess;
};

// Scores `est` against `ref` (both width * height vectors) over the pixels where `mask` is non-zero
// (empty: every pixel) and both vectors are non-zero. `ref_stderr` (degrees per pixel) may be
// empty. Returns nothing when no pixel qualifies. Throws InputError on size mismatches and on NaN
// or infinite vectors at compared pixels (naming the image and the pixel).
std::optional<BentMetrics> compare_bent(int width, int height, const std::vector<glm::vec3>& ref,
                                        const std::vector<glm::vec3>& est,
                                        const std::vector<uint8_t>& mask,
                                        const std::vector<float>& ref_stderr);

// The keys above, with `prefix` before each (e.g. "true_"), added to `out` (a JSON object).
void add_bent_json(const BentMetrics& m, nlohmann::json& out, const std::string& prefix = "");

// bent_pixels, bent_angle_mean, bent_angle_p95, bent_ref_stderr, bent_angle_excess.
std::vector<std::string> bent_metric_keys();

// The bent normal of an estimate's extra channels bent.X/Y/Z, or nothing when it has none.
std::optional<std::vector<glm::vec3>> bent_of_channels(const std::vector<float>* x,
                                                       const std::vector<float>* y,
                                                       const std::vector<float>* z);

}  // namespace aoeval
