// `aoeval compare --sequence REFDIR ESTDIR (--motion GBUFDIR | --static) [--json FILE]`: the
// sequence keys of CONTRACT §10 over two frame folders, scored by harness/scoring/temporal.h with
// each frame built by temporal_frame() as the session's frames are (harness/evaluation/frames.cpp).
//
// A frame folder holds frame_KKKK.exr for K = 0, 1, ..., N - 1 (four digits or more, no gaps;
// other files are ignored): REFDIR the references (AO, A, optional AO_stderr: `aoeval reference
// --frame K`), ESTDIR the estimates (AO, A), GBUFDIR the G-buffers (`aoeval gbuffer --frame K`)
// whose motion.X/Y and disoccluded say where each pixel was in frame K - 1. A run's kept frames
// have this layout (harness/sweep/kept_sequence.h). --static instead says that nothing moves:
// zero motion, nothing disoccluded.
//
// A reference frame whose AO and AO_stderr are frame K - 1's bit for bit is taken as the same
// trace (issue 42: a frame that poses what frame K - 1 did reuses its reference, and a run keeps
// it as a hard link), so its noise is shared and the temporal keys remove none of it, as the
// session's scoring does (TemporalFrame::ref_repeats_previous). Two independent traces of a
// reference with any noise never agree in every pixel.
#include "cmd/compare_sequence.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <regex>

#include "base/errors.h"
#include "base/text_files.h"
#include "harness/scoring/temporal_frame.h"
#include "harness/sweep/kept_references.h"
#include "scenes/ao_exr.h"
#include "scenes/gbuffer.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

// The frame files of a folder, frame 0 first; InputError naming the folder and the first missing
// frame when frames are not 0..N-1.
std::vector<std::string> frame_files(const std::string& dir, const std::string& option) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(option + " " + dir + ": not a folder of frame_KKKK.exr files");
  static const std::regex name(R"(frame_([0-9]{4,9})\.exr)");
  std::map<int, std::string> found;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::smatch match;
    const std::string file = entry.path().filename().string();
    if (!std::regex_match(file, match, name)) continue;
    const int k = std::stoi(match[1]);
    if (!found.emplace(k, entry.path().string()).second)
      throw InputError(dir + ": two files for frame " + std::to_string(k) + " (" + file + ", " +
                       fs::path(found[k]).filename().string() + ")");
  }
  if (found.empty()) throw InputError(option + " " + dir + ": no frame_KKKK.exr file in it");
  std::vector<std::string> files;
  for (const auto& [k, path] : found) {
    const int expected = static_cast<int>(files.size());
    if (k != expected)
      throw InputError((fs::path(dir) / frame_file_name(expected)).string() +
                       ": missing (frames must run 0.." + std::to_string(found.rbegin()->first) +
                       " without gaps)");
    files.push_back(path);
  }
  return files;
}

// `other` must hold the frames `ref` holds, no fewer and no more.
void check_same_frames(const std::vector<std::string>& ref, const std::string& ref_dir,
                       const std::vector<std::string>& other, const std::string& other_dir) {
  if (other.size() < ref.size())
    throw InputError(
        (fs::path(other_dir) / frame_file_name(static_cast<int>(other.size()))).string() +
        ": missing (" + ref_dir + " has " + std::to_string(ref.size()) + " frames)");
  if (other.size() > ref.size())
    throw InputError(other[ref.size()] + ": no such frame in " + ref_dir + " (" +
                     std::to_string(ref.size()) + " frames)");
}

void check_size(const std::string& path, int w, int h, int w0, int h0, const std::string& first) {
  if (w != w0 || h != h0)
    throw InputError(path + ": size " + size_text(w, h) + " differs from " + first + " (" +
                     size_text(w0, h0) + ")");
}

}  // namespace

nlohmann::json compare_sequence(const SequenceCompareInput& in) {
  if (in.motion_dir.empty() == !in.assume_static)
    throw InputError(in.assume_static
                         ? "compare --sequence: --motion and --static exclude each other"
                         : "compare --sequence: give --motion GBUFDIR (frame_KKKK.exr "
                           "from `aoeval gbuffer --frame K`) or --static (nothing "
                           "moves)");
  const std::vector<std::string> refs = frame_files(in.ref_dir, "REFDIR");
  const std::vector<std::string> ests = frame_files(in.est_dir, "ESTDIR");
  check_same_frames(refs, in.ref_dir, ests, in.est_dir);
  std::vector<std::string> gbuffers;
  if (!in.motion_dir.empty()) {
    gbuffers = frame_files(in.motion_dir, "--motion");
    check_same_frames(refs, in.ref_dir, gbuffers, in.motion_dir);
  }
  TemporalScorer scorer;
  nlohmann::json by_frame = nlohmann::json::array();
  int w0 = 0, h0 = 0;
  GBuffer prev_g;
  AoExr prev_ref;
  for (size_t k = 0; k < refs.size(); ++k) {
    AoExr ref = read_ao_exr(refs[k]);
    const AoExr est = read_ao_exr(ests[k]);
    if (k == 0) {
      w0 = ref.width;
      h0 = ref.height;
    }
    check_size(ref.path, ref.width, ref.height, w0, h0, refs[0]);
    check_size(est.path, est.width, est.height, w0, h0, refs[0]);
    GBuffer g;
    if (!gbuffers.empty()) {
      g = read_gbuffer(gbuffers[k]);
      check_size(gbuffers[k], g.width, g.height, w0, h0, refs[0]);
      if (g.motion.empty())
        throw InputError(gbuffers[k] +
                         ": no motion.X, motion.Y and disoccluded channels (write "
                         "it with `aoeval gbuffer --frame " +
                         std::to_string(k) + "`)");
    }
    std::vector<uint8_t> mask(ref.ao.size());
    for (size_t p = 0; p < mask.size(); ++p) mask[p] = ref.covered(p) && est.covered(p);
    const bool repeats = k > 0 && same_bits(ref.ao, prev_ref.ao) &&
                         same_bits(ref.stderr_ao, prev_ref.stderr_ao) &&
                         same_bits(ref.coverage, prev_ref.coverage);
    const double excess = scorer.add_frame(
        temporal_frame(w0, h0, est.ao.data(), ref.ao.data(), ref.stderr_ao, mask, &g,
                       k > 0 ? prev_g.camera.jitter : glm::vec2(0.0f), repeats));
    by_frame.push_back(std::isfinite(excess) ? nlohmann::json(excess) : nlohmann::json());
    prev_g = std::move(g);
    prev_ref = std::move(ref);
  }
  nlohmann::json out = scorer.scores();
  out["rmse_excess_by_frame"] = by_frame;
  return out;
}

}  // namespace aoeval
