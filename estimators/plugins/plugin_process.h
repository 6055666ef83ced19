// Process plug-ins (CONTRACT §7): someone else's program, run once per frame request.
//
// prepare() makes a private folder (mkdtemp under $TMPDIR) and writes into it the shared G-buffer
// (`G.exr`, CONTRACT §4 channels, the camera in its aoeval:camera header attribute) and the
// effective parameters (`P.json`, one object: name -> value, defaults included). run() starts
//     <command...> --gbuffer G.exr --params P.json --out AO.exr --frames N
// (absolute paths; argv, no shell; working folder = the plug-in folder; stdin /dev/null, stdout
// and stderr to files in the private folder) as the leader of its own process group, waits at
// most timeout_s and then kills the whole group; after a normal exit it kills the group too, so
// nothing the program left running in the background survives. Descendants that left the group
// (setsid) are killed as well: aoeval makes itself their child subreaper (PR_SET_CHILD_SUBREAPER)
// and kills and reaps every descendant of the program, and every orphan it adopted outside its own
// process group, until none is left. Only the last 64 KiB of stderr are read for the quoted line.
// The private folder is removed when the estimator is destroyed.
//
// Output checks, each a failure that becomes EstimatorUnavailable("plug-in NAME: <reason>: <last
// stderr line>"), i.e. a "skipped: ..." results row, and the run carries on: non-zero exit, death
// by a signal, time-out, no AO.exr, an unreadable AO.exr, a size other than the G-buffer's, no
// channel AO, NaN or infinity in a covered pixel, an AO value outside [0, 1] by more than
// kAoRangeSlack, a declared bent output missing or non-finite, a malformed timing file.
//
// Range rule: values within kAoRangeSlack of [0, 1] are clamped into it (float rounding in the
// program's arithmetic, e.g. 1 - sum giving 1.0000001); anything further out is rejected, not
// clamped: it means the program computes something other than accessibility, and clamping would
// hide that behind plausible numbers. Uncovered pixels (A = 0) are ignored.
//
// Timing: when the program writes AO.exr.timing.json {"frame_ms": [...], "passes_ms": {"name":
// [...]}}, the frame's time is the median of its frame_ms ("total_ms"; timing_source
// "plugin-frames") and each pass's median is "<name>_ms"; otherwise the time is the whole
// process's wall clock, start-up and file I/O included (timing_source "process-wall"). Either way
// "process_ms" records the whole process's wall clock.
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/plugins/plugin_manifest.h"
#include "scenes/ao_exr.h"

namespace aoeval {

// kAoRangeSlack: scenes/ao_exr.h, the one rule for AO values read from any file.

struct ProcessOutcome {
  bool started = false;  // false: fork failed (reason in `error`)
  bool timed_out = false;
  int exit_code = -1;  // when it exited
  int signal = 0;      // when a signal ended it
  double wall_ms = 0.0;
  std::string error;
};

// Runs argv[0] (searched on PATH unless it holds a '/', then relative to `cwd`) with argv in `cwd`
// as a new process group, stdin from /dev/null, stdout and stderr appended to the two files, for
// at most timeout_s; kills the group and every descendant (SIGKILL) on time-out and after it ends.
// Never throws for the program's failures.
ProcessOutcome run_process(const std::vector<std::string>& argv, const std::string& cwd,
                           double timeout_s, const std::string& stdout_path,
                           const std::string& stderr_path);

// The pieces run_process is made of, which the frames protocol (plugin_frames.h) shares:
// start_plugin_process forks argv[0] (as above) in `cwd` as the leader of a new process group with
// descriptors 0, 1, 2 = in_fd, out_fd, err_fd (pass FD_CLOEXEC ones: nothing else of aoeval's is
// inherited) and returns its pid, or -1 with `error`; wait_for_plugin_exit waits at most
// timeout_ms for it to end, without reaping it; end_plugin_process kills its process group and
// every descendant (the subreaper's sweep), reaps it, and sets o.exit_code or o.signal unless
// o.timed_out.
pid_t start_plugin_process(const std::vector<std::string>& argv, const std::string& cwd, int in_fd,
                           int out_fd, int err_fd, std::string& error);
bool wait_for_plugin_exit(pid_t pid, double timeout_ms);
void end_plugin_process(pid_t pid, ProcessOutcome& o);
// "" when the program started and exited with status 0, else why not ("timed out after N s
// (process group killed)", "killed by signal 11 (SEGV)", "exited with status 3", ...).
std::string process_failure(const ProcessOutcome& o, double timeout_s);

// A process plug-in's private folder (mkdtemp under $TMPDIR, made on first use, removed with the
// object): write_inputs writes G.exr (the G-buffer of `context`, CONTRACT §4 channels, motion and
// disoccluded on sequence frames, the camera in its aoeval:camera attribute) and P.json (`params`).
class PluginFolder {
 public:
  explicit PluginFolder(std::string plugin_name) : name_(std::move(plugin_name)) {}
  ~PluginFolder();
  PluginFolder(const PluginFolder&) = delete;
  PluginFolder& operator=(const PluginFolder&) = delete;
  void write_inputs(const EstimateContext& context, const nlohmann::json& params);
  const std::string& path() const { return path_; }

 private:
  std::string name_, path_;
};

// The last non-empty line of a text file (at most 300 characters), "" when there is none.
std::string last_line_of(const std::string& path);

// Reads a plug-in's AO.exr (and AO.exr.timing.json when present) for G-buffer `g` into `result`.
// Returns "" on success, else the reason it is rejected.
std::string read_process_output(const std::string& ao_path, const GBuffer& g, bool bent,
                                EstimateResult& result);

std::unique_ptr<Estimator> make_process_estimator(const PluginManifest& m, const ParamSet& params);

}  // namespace aoeval
