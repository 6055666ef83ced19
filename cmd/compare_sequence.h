// `aoeval compare --sequence` (cmd_compare.cpp's option): the sequence keys of CONTRACT §10 over
// two frame folders (the layout is in compare_sequence.cpp's header and README "AO over time").
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace aoeval {

struct SequenceCompareInput {
  std::string ref_dir, est_dir;
  std::string motion_dir;      // G-buffers with motion ("" with assume_static)
  bool assume_static = false;  // --static: zero motion, nothing disoccluded
};

// TemporalScorer::scores() of the folders, plus "rmse_excess_by_frame". InputError (exit 2)
// naming the folder or file: a missing, extra or out-of-sequence frame, a size that differs from
// frame 0's or between reference and estimate, a G-buffer without motion, neither or both of
// --motion and --static, and whatever read_ao_exr refuses.
nlohmann::json compare_sequence(const SequenceCompareInput& input);

}  // namespace aoeval
