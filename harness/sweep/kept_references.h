// The references a run's rows were scored against, kept in its output folder (references/), so
// that its report (mosaics, the viewer) and `aoeval merge` find them without the cache. Used by the
// suite runner and the sweep runner.
//
// Compact by default (issue 42: the default suite's references/ was 431 MB, then 271 MB): a kept
// EXR holds every value rounded to float16 precision (10 mantissa bits: within 4.9e-4 of the
// cache's floats for values in [0, 1], far inside a reference's own stderr) and is still a 32-bit
// float EXR (CONTRACT §4), PXR24 compressed, which stores those values bit for bit
// (write_half_precision_exr). A sequence frame's kept reference holds AO, AO_stderr and A only
// (what `aoeval compare --sequence` and the viewer read), a kept sequence frame estimate AO and A
// (kept_sequence.h); a still reference keeps every channel, a row's estimate EXR every channel.
// The viewer's compact data are float16 too, so its probe returns exactly the kept file's values.
// A frame whose cache entry is one already kept (a frame that does not change reuses its
// predecessor's reference) is a hard link to that file, not a second copy. `exact` (`aoeval
// sweep`, `aoeval run --viewer-exact`): bit-for-bit, zip-compressed copies of the cache entries,
// every channel, as before.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "harness/evaluation/evaluation.h"
#include "scenes/exr_io.h"

namespace aoeval {

class KeptReferences {
 public:
  explicit KeptReferences(std::string out, bool exact = false)
      : out_(std::move(out)), exact_(exact) {}
  bool exact() const { return exact_; }
  // The reference EXR for (scene, view, resolution, definition) under <out>/references/, copied
  // (atomically, once per run) from the content-addressed cache the session filled; returns its
  // path relative to the output folder.
  std::string keep(EvaluationSession& session, const std::string& scene_name, const View& view,
                   int w, int h, const AoDefinition& definition);
  // Frame k of a sequence view's reference, copied from `cache_path` (the entry its frame was
  // scored against, KeptFrame::reference_cache) to references/<keep()'s name>/frame_KKKK.exr, the
  // layout `aoeval compare --sequence` reads; returns that path relative to the output folder.
  std::string keep_frame(EvaluationSession& session, const std::string& scene_name,
                         const View& view, int w, int h, const AoDefinition& definition, int frame,
                         const std::string& cache_path);

 private:
  std::string stem(EvaluationSession& session, const std::string& scene_name, const View& view,
                   int w, int h, const AoDefinition& definition) const;
  // `frame`: a sequence frame's reference (compact: AO, AO_stderr and A only).
  void copy(const std::string& from, const std::string& rel, bool frame);
  std::string out_;
  bool exact_ = false;
  std::set<std::string> written_;
  std::map<std::string, std::string> kept_from_;  // cache entry -> the file kept from it
};

// A run's still estimate EXR at `path`, compact (issue 42; not `exact`): AO, A and AO_stderr are
// PXR24-compressed, which rounds a float32 to the nearest of 15 mantissa bits (OpenEXR's
// floatToFloat24: A's 0 and 1 stay exact; AO in [0, 1] moves by at most 2^-17 = 7.7e-6, far
// inside the dashboard's 1e-4 per pixel for deterministic estimators, CONTRACT §12); every other
// channel (bent.X/Y/Z, obscurance.R/G/B, AO_horizon, ...) is rounded first, which PXR24 keeps bit
// for bit: bent.X/Y/Z as a kept reference's (kept_rounding: 1/512, a direction within 0.097
// degrees), every other extra to the nearest multiple of 1/2048 (within 2.44e-4), where every
// value of the channel is finite and within +-kKeptFixedRange, else to float16 (within 4.9e-4 of
// values in [0, 1]). Still a 32-bit float EXR (CONTRACT §4). Rewritten atomically, header kept.
// The row's keys are computed before, from the estimator's floats.
void compact_estimate_extras(const std::string& path);
// The same for an estimate still in memory, written once at `path` with `attributes`: what a suite
// run's session writes (EvaluationSession::set_estimate_writer), instead of writing the estimate
// and then reading it back to rewrite it.
void write_compact_estimate(const std::string& path, const OIIO::ImageBuf& image,
                            const Attributes& attributes);
// A sequence point's flicker and lag maps (maps.exr, kept_sequence.h) at `path`: every channel
// rounded to the nearest multiple of 1/kKeptMapStep (within 1.22e-4; the viewer's fixed-point
// planes hold the same values) where every value of the channel is finite and within
// +-kKeptFixedRange, else to float16, PXR24-compressed (the default suite's 28 maps 6.8 -> 2.7 MB
// against float32 with zip). The maps are rms statistics over frames, shown through a colour map;
// the rows' keys are computed before, from the floats.
inline constexpr int kKeptMapStep = 4096;
void write_compact_maps(const std::string& path, const OIIO::ImageBuf& maps,
                        const Attributes& attributes);
// What PXR24 makes of `v` (OpenEXR's floatToFloat24, read back): nearest of 15 mantissa bits,
// ties away from zero; infinities and NaN stay so. For the tests and the README's bound.
float at_pxr24_precision(float v);

// `image` with every value rounded to the nearest float16 (round to nearest even; a value beyond
// float16's range is kept as it is), still float32: what the compact kept files hold.
OIIO::ImageBuf at_half_precision(const OIIO::ImageBuf& image);

// `image`'s channels `names`, in that order; InputError naming `path` when one is missing.
OIIO::ImageBuf only_channels(const OIIO::ImageBuf& image, const std::vector<std::string>& names,
                             const std::string& path);
// What a compact kept file holds (issue 42), channel by channel (kept_rounding):
// - AO_stderr and bent_stderr to kKeptStderrBits significant bits, down or up at random with the
//   probabilities that keep its square unbiased (at_significant_bits with kept_dither, a hash of
//   the pixel and channel: the same image, the same bits): within one step of the value (1/4 of
//   it at most, 1/8 near the top of each octave; about 6.7 % rms on the default suite's
//   references). What every noise removal reads is mean(stderr^2) (rmse_excess, the temporal
//   keys), which stays unbiased; rounding to the nearest instead moved it by -1.1 % on the
//   default suite's references (their stderr takes few distinct values: 8 replicate means of 0/1
//   visibilities), and `compare --sequence`'s temporal_rmse_excess on the kept files by +2 to
//   +4 %. A reference's stderr is itself an estimate from 8 replicate means (7 degrees of freedom:
//   about 27 % relative standard deviation); the rounding adds about 3 % to that spread. Every
//   such value is a float16, so the viewer's float16 stderr equals the file's.
// - bent.X/Y/Z to the nearest multiple of 1/kKeptBentStep (within 9.8e-4 per component: a unit
//   bent normal's direction moves by at most 0.097 degrees, against the default references'
//   own bent noise of degrees, bent_stderr).
// Each only when every value of the channel is finite and within +-kKeptFixedRange; every other
// channel (and such a channel otherwise) at float16 precision (at_half_precision).
inline constexpr float kKeptFixedRange = 2.0f;
inline constexpr int kKeptStderrBits = 3;
inline constexpr int kKeptBentStep = 512;
struct KeptRounding {
  enum Kind { half, fixed, significant } kind = half;
  int value = 0;  // fixed: the step is 1/value; significant: the number of significant bits
};
KeptRounding kept_rounding(const std::string& channel);
OIIO::ImageBuf at_kept_precision(const OIIO::ImageBuf& image);
// `v` at the nearest multiple of 1/step (a float32: exact for |v * step| < 2^24).
float at_fixed_step(float v, int step);
// `v` with `bits` significant bits: of the two such values around it, lo <= |v| < hi, hi when
// `u` (uniform on [0, 1)) is below (v^2 - lo^2) / (hi^2 - lo^2), so that E[result^2] = v^2; `v`
// itself when it has no more bits. At float16 precision below float16's normal range (2^-14);
// every result is a float16. NaN and infinities stay.
float at_significant_bits(float v, int bits, double u);
// The kept files' uniform on [0, 1) for (pixel, channel): a hash, so a kept file is a function
// of its image.
double kept_dither(uint64_t pixel, int channel);
// True when PXR24 stores every value of `image` bit for bit (each finite and within 15 mantissa
// bits: float16 values, multiples of 1/4096 within +-2, ...).
bool pxr24_keeps_bits(const OIIO::ImageBuf& image);
// Writes `image` at kept precision (at_kept_precision) as a 32-bit float EXR, read back bit for
// bit: PXR24 when it keeps every value (pxr24_keeps_bits): PXR24 keeps 15 of float32's 23
// mantissa bits, so it stores float16's 10 exactly, and its 24-bit words deflate far better than
// zip's 32-bit ones (the default suite's kept references 1.35x smaller, still frames 1.25x). Zip
// where some value is beyond float16's range or not finite (PXR24 would round it).
// DWAB (lossless for channels whose name's last part is not R, G, B, Y, BY or RY, and 27 % smaller
// on the default suite's kept reference frames) was measured and not taken: OpenEXR 3.1.5 takes
// about 170 ms to write one 320x240 frame with it against 9 ms with PXR24, which made the kept
// frames 133 s of the cold default run's background work (22 s with PXR24) and its wall time 338 s.
void write_half_precision_exr(const std::string& path, const OIIO::ImageBuf& image,
                              const Attributes& attributes);

// "frame_0007.exr": the name of frame k in a frame folder (kept estimates and references, and
// what `aoeval compare --sequence` reads).
std::string frame_file_name(int frame);

}  // namespace aoeval
