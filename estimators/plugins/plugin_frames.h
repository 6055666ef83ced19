// Process plug-ins over time: "protocol": "frames" (CONTRACT §10). The program is started once per
// estimator instance, i.e. once per sequence point (EstimatorInfo::keeps_state: one instance runs
// every frame in order) or once per still view (its warm-up and timed runs are frames too), as
//     <command...>
// with no arguments added, in the plug-in folder, as the leader of its own process group, with
// stdin and stdout one Unix socket to aoeval and stderr appended to a file in the private folder
// (plugin_process.h: the same start, subreaper and kill as the per-run protocol). For each frame
// aoeval writes G.exr and P.json (the frame's G-buffer with motion and disoccluded, and the
// parameters with the seed rule applied: seed + k) and sends one line
//     {"frame": K, "gbuffer": "/abs/G.exr", "params": "/abs/P.json", "out": "/abs/AO.exr"}
// and waits at most timeout_s for one line back, {"frame": K, "ok": true} after writing AO.exr
// (optionally AO.exr.timing.json for that frame), or {"frame": K, "error": "why"}. After the last
// frame aoeval shuts its end for writing (EOF on the program's stdin: exit), waits at most
// kFramesExitGraceS for it to end, then kills its process group and every descendant.
//
// Every failure is an EstimatorUnavailable "plug-in NAME <reason>: <last stderr line>" (a
// skipped row), and ends the program (the next run of the instance starts it again): no answer
// within timeout_s; the program's end (exit, signal) or its stdout closed before answering; a
// line that is not a JSON object {"frame": K, "ok": true} or {"frame": K, "error": "..."}, quoted
// (at most 120 characters); another frame number; an error it reports; anything it writes to
// stdout between frames; a line longer than kMaxAnswerBytes; and each output check of the per-run
// protocol (read_process_output: no AO.exr, wrong size, NaN, out of range...).
//
// Timing: the frame's time is the median of AO.exr.timing.json's frame_ms when written
// (timing_source "plugin-frames"), else the wall clock from the request to the answer
// ("frame-wall"); "process_ms" is that round trip either way. The first frame's round trip holds
// the program's own start-up (its imports), which the per-run protocol pays every frame.
#pragma once

#include <memory>
#include <string>

#include "estimators/estimator.h"
#include "estimators/plugins/plugin_manifest.h"

namespace aoeval {

inline constexpr size_t kMaxAnswerBytes = 64 * 1024;  // one answer line, newline excluded
inline constexpr double kFramesExitGraceS = 2.0;      // after EOF, before the kill

// The process protocols, run and frames, explained: the second part of `aoeval estimators abi`.
std::string process_protocol_text();

std::unique_ptr<Estimator> make_frames_process_estimator(const PluginManifest& m,
                                                         const ParamSet& params);

}  // namespace aoeval
