// Process plug-ins: the protocol, and one test per way someone else's program can fail, each made
// by a tiny broken plug-in written here. Every failure must be an EstimatorUnavailable whose reason
// quotes the program's last stderr line (the harness turns it into a "skipped: ..." row and goes
// on: harness/plugins/plugins_cli_test.cpp checks that part), and leave no file behind.
#include "estimators/plugins/plugin_process.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <sstream>

#include "base/errors.h"

#include "estimators/plugins/plugin_test_util.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;
using plugin_test::make_plugin;
using plugin_test::run_plugin;
using testutil::test_temp_dir;

// A floor seen with a horizontal view axis: the top half of the image is sky (not covered), the
// bottom half floor.
const TestView& floor_view() {
  static const TestView view = [] {
    View v;
    v.eye = glm::vec3(0.0f, 1.0f, 0.0f);
    v.target = glm::vec3(0.0f, 1.0f, -5.0f);
    v.fov_y_deg = 60.0f;
    return render_view(scene_of({generated("floor", "plane", {{"size", {60, 60}}})}), v, 32, 24);
  }();
  return view;
}

std::string shell_plugin(const std::string& name, const std::string& script,
                         double timeout_s = 20.0, const std::string& extra = "") {
  const fs::path dir = test_temp_dir("process") / name;
  return make_plugin(dir,
                     R"({"name": ")" + name + R"(", "summary": "test", "kind": "process",
                         "command": ["/bin/sh", "plugin.sh"], "timeout_s": )" +
                         format_param_value(timeout_s) + extra + R"(,
                         "definition": {"weighting": "cosine"}})",
                     {{"plugin.sh", script}});
}

// A one-channel-per-name EXR with `value(i, j)` everywhere, in the plug-in folder as `file`.
void write_ao(const std::string& folder, const std::string& file, int w, int h,
              const std::vector<std::string>& channels,
              const std::function<float(int, int)>& value) {
  OIIO::ImageSpec spec(w, h, static_cast<int>(channels.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = channels;
  OIIO::ImageBuf image(spec);
  auto* px = static_cast<float*>(image.localpixels());
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (size_t c = 0; c < channels.size(); ++c)
        px[(static_cast<size_t>(j) * w + i) * channels.size() + c] = value(i, j);
  ASSERT_TRUE(image.write(folder + "/" + file));
}

// The folder the estimator's private files go to, emptied; the tests check it is empty after.
fs::path private_tmp() {
  const fs::path tmp = test_temp_dir("process") / "tmp";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  setenv("TMPDIR", tmp.c_str(), 1);
  return tmp;
}

std::string failure_of(const std::string& folder) {
  const fs::path tmp = private_tmp();
  std::string reason;
  try {
    run_plugin(folder, floor_view());
  } catch (const EstimatorUnavailable& e) {
    reason = e.what();
  }
  EXPECT_TRUE(fs::is_empty(tmp)) << "files left in " << tmp;
  return reason;
}

void expect_reason(const std::string& reason, const std::vector<std::string>& parts) {
  EXPECT_FALSE(reason.empty()) << "the plug-in did not fail";
  for (const auto& p : parts)
    EXPECT_NE(reason.find(p), std::string::npos) << p << " in: " << reason;
}

// The last pixel row is floor (covered); the top row is sky (not covered).
TEST(ProcessPlugin, TheFloorViewHasBothCoveredAndUncoveredPixels) {
  const GBuffer& g = floor_view().gbuffer;
  EXPECT_FALSE(g.covered(g.index(0, 0)));
  EXPECT_TRUE(g.covered(g.index(0, g.height - 1)));
}

TEST(ProcessPlugin, RunsTheProtocolAndReadsTheTimingFile) {
  // The program checks its arguments, copies P.json's radius into AO and reports two frames.
  const std::string dir = shell_plugin("ok", R"(
set -e
[ "$1" = --gbuffer ] && [ -s "$2" ] && [ "$3" = --params ] && [ "$5" = --out ] && [ "$7" = --frames ]
[ "$8" = 3 ] || { echo "frames $8" >&2; exit 9; }
cp ao_quarter.exr "$6"
echo '{"frame_ms": [2, 4, 30], "passes_ms": {"ao": [1, 1, 5]}}' > "$6.timing.json"
)",
                                       20.0, R"(, "frames": 3)");
  write_ao(dir, "ao_quarter.exr", 32, 24, {"AO"}, [](int, int) { return 0.25f; });
  const fs::path tmp = private_tmp();
  {
    const EstimateResult r = run_plugin(dir, floor_view());
    const GBuffer& g = floor_view().gbuffer;
    for (size_t k = 0; k < g.pixel_count(); ++k) EXPECT_EQ(r.ao[k], g.covered(k) ? 0.25f : 0.0f);
    EXPECT_EQ(r.timing_source, "plugin-frames");
    EXPECT_EQ(r.pass_ms.at("total_ms"), 4.0);  // the median of its frames
    EXPECT_EQ(r.pass_ms.at("ao_ms"), 1.0);
    EXPECT_GT(r.pass_ms.at("process_ms"), 0.0);
  }
  EXPECT_TRUE(fs::is_empty(tmp));
}

TEST(ProcessPlugin, WithoutATimingFileTheWholeProcessIsTimed) {
  const std::string dir = shell_plugin("untimed", "cp ao_one.exr \"$6\"\n");
  write_ao(dir, "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  const EstimateResult r = run_plugin(dir, floor_view());
  EXPECT_EQ(r.timing_source, "process-wall");
  EXPECT_EQ(r.pass_ms.at("total_ms"), r.pass_ms.at("process_ms"));
}

TEST(ProcessPlugin, ParamsJsonHoldsEveryEffectiveParameter) {
  const fs::path dir = test_temp_dir("process") / "params";
  make_plugin(dir, R"({"name": "params", "summary": "s", "kind": "process",
      "command": ["/bin/sh", "plugin.sh"], "definition": {"weighting": "cosine"},
      "params": [{"name": "r", "type": "real", "default": 0.5, "min": 0, "max": 1, "meaning": "m"},
                 {"name": "n", "type": "integer", "default": 3, "min": 1, "max": 9, "meaning": "m"}]})",
              {{"plugin.sh", "cp \"$4\" seen.json; cp ao_one.exr \"$6\"\n"}});
  write_ao(dir.string(), "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  run_plugin(dir.string(), floor_view(), {{"n", "7"}});
  std::ifstream in(dir / "seen.json");
  EXPECT_EQ(nlohmann::json::parse(in), (nlohmann::json{{"r", 0.5}, {"n", 7}}));
}

TEST(ProcessPlugin, NonZeroExitQuotesTheLastStderrLine) {
  expect_reason(
      failure_of(shell_plugin("exit3", "echo first >&2\necho 'boom: no GPU' >&2\nexit 3\n")),
      {"plug-in exit3 exited with status 3: boom: no GPU"});
}

TEST(ProcessPlugin, ACrashBySignal) {
  expect_reason(failure_of(shell_plugin("segv", "echo 'about to crash' >&2\nkill -SEGV $$\n")),
                {"killed by signal 11 (SEGV): about to crash"});
}

// The program is checked when the manifest is read: a bare name is looked up in the plug-in
// folder first, then on PATH; a missing or non-executable program is an InputError naming it.
TEST(ProcessPlugin, ACommandIsResolvedInTheFolderThenOnPathAndCheckedAtLoad) {
  const fs::path dir = test_temp_dir("process") / "bare";
  const std::string manifest = R"({"name": "bare", "summary": "s", "kind": "process",
      "command": ["prog.sh"], "definition": {"weighting": "cosine"}})";
  make_plugin(dir, manifest,
              {{"prog.sh", "#!/bin/sh\ncp \"$(dirname \"$0\")/ao_one.exr\" \"$6\"\n"}});
  auto error_of = [&]() -> std::string {
    try {
      read_plugin_manifest(dir.string());
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  expect_reason(error_of(), {"command[0]: " + (dir / "prog.sh").string() +
                             " is not an executable file (chmod +x it"});
  fs::permissions(dir / "prog.sh", fs::perms::owner_exec, fs::perm_options::add);
  write_ao(dir.string(), "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  EXPECT_EQ(read_plugin_manifest(dir.string()).command[0], (dir / "prog.sh").string());
  EXPECT_EQ(run_plugin(dir.string(), floor_view()).ao.back(), 1.0f);
  fs::remove(dir / "prog.sh");
  expect_reason(error_of(), {"command[0]: \"prog.sh\" is neither a file in the plug-in folder "
                             "nor a program on PATH"});
  make_plugin(dir, R"({"name": "bare", "summary": "s", "kind": "process",
      "command": ["./no-such-program"], "definition": {"weighting": "cosine"}})");
  expect_reason(error_of(), {"command[0]: " + (dir / "no-such-program").string() +
                             " is not an executable file"});
  make_plugin(dir, R"({"name": "bare", "summary": "s", "kind": "process",
      "command": ["sh", "-c", "true"], "definition": {"weighting": "cosine"}})");
  EXPECT_EQ(read_plugin_manifest(dir.string()).command[0], "sh");  // on PATH
}

bool process_with_argument_exists_now(const std::string& marker) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    std::ifstream in(entry.path() / "cmdline");
    std::string cmdline((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (char& c : cmdline)
      if (c == '\0') c = ' ';
    if (cmdline.find(marker) != std::string::npos && cmdline.find("sleep") != std::string::npos)
      return true;
  }
  return false;
}

// SIGKILL is delivered asynchronously: a killed process may still be listed for a moment after
// kill() returns. One that survived would still be there after a second (it sleeps for an hour).
bool process_with_argument_exists(const std::string& marker) {
  for (int i = 0; i < 100; ++i) {
    if (!process_with_argument_exists_now(marker)) return false;
    usleep(10000);
  }
  return true;
}

TEST(ProcessPlugin, ATimeOutKillsTheWholeProcessGroupInTime) {
  // A background child that would outlive its parent, then a parent that never finishes.
  const std::string marker = "3600.1" + std::to_string(getpid() % 1000);
  const std::string dir = shell_plugin(
      "slow", "sleep " + marker + " &\necho 'still thinking' >&2\nsleep 30\n", /*timeout_s=*/1.0);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string reason = failure_of(dir);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  expect_reason(reason, {"timed out after 1 s (process group killed): still thinking"});
  // The plug-in would run 30 s; the bound sits far from both that and the 1 s time-out so that a
  // loaded machine (python and shell start-up under CI) does not fail a time-out that worked.
  EXPECT_LT(s, 10.0) << "the time-out (1 s) and start-up, well short of the 30 s sleep";
  EXPECT_FALSE(process_with_argument_exists(marker)) << "a child survived";
}

TEST(ProcessPlugin, ABackgroundChildDiesWithANormalExitToo) {
  const std::string marker = "3600.2" + std::to_string(getpid() % 1000);
  const std::string dir = shell_plugin("leaky", "sleep " + marker + " &\ncp ao_one.exr \"$6\"\n");
  write_ao(dir, "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  run_plugin(dir, floor_view());
  EXPECT_FALSE(process_with_argument_exists(marker));
}

// The processes whose parent is this one (zombies included): none may be left by a plug-in.
std::vector<std::string> children_of_this_process() {
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(entry.path() / "stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t paren = text.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream fields(text.substr(paren + 1));
    char state = 0;
    pid_t ppid = 0;
    if (fields >> state >> ppid && ppid == getpid()) found.push_back(text.substr(0, paren + 1));
  }
  return found;
}

// A grandchild that leaves the process group and the session (setsid) is killed too, whether the
// plug-in ends normally, times out, or its shell has already exited: aoeval is the subreaper.
TEST(ProcessPlugin, ASetsidGrandchildIsKilledAndReaped) {
  const std::string a = "3600.3" + std::to_string(getpid() % 1000);
  const std::string b = "3600.4" + std::to_string(getpid() % 1000);
  const std::string c = "3600.5" + std::to_string(getpid() % 1000);
  std::string dir = shell_plugin("escapes", "setsid sleep " + a + " &\ncp ao_one.exr \"$6\"\n");
  write_ao(dir, "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  run_plugin(dir, floor_view());
  EXPECT_FALSE(process_with_argument_exists(a)) << "a setsid grandchild survived a normal exit";
  // Its parent (a subshell) exits at once: the grandchild is an orphan before the plug-in ends.
  dir = shell_plugin("escapes-orphan",
                     "(setsid sleep " + b + " &)\nsleep 0.2\ncp ao_one.exr \"$6\"\n");
  write_ao(dir, "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  run_plugin(dir, floor_view());
  EXPECT_FALSE(process_with_argument_exists(b)) << "an orphaned setsid grandchild survived";
  dir = shell_plugin("escapes-slow", "setsid sleep " + c + " &\nsleep 30\n", /*timeout_s=*/1.0);
  expect_reason(failure_of(dir), {"timed out after 1 s"});
  EXPECT_FALSE(process_with_argument_exists(c)) << "a setsid grandchild survived a time-out";
  EXPECT_EQ(children_of_this_process(), std::vector<std::string>{}) << "unreaped children";
}

// 50 MB on stderr: the reason still quotes the last line, read from the file's tail only (a
// bounded read: the last 64 KiB), and a last line longer than the tail is cut, not loaded.
TEST(ProcessPlugin, FiftyMegabytesOfStderrKeepTheLastLine) {
  expect_reason(failure_of(shell_plugin("chatty",
                                        "head -c 50000000 /dev/zero | tr '\\0' 'x' >&2\n"
                                        "echo >&2\necho 'the last words' >&2\nexit 3\n")),
                {"exited with status 3: the last words"});
  const std::string reason = failure_of(
      shell_plugin("one-line", "head -c 50000000 /dev/zero | tr '\\0' 'y' >&2\nexit 3\n"));
  expect_reason(reason, {"exited with status 3: ...yyyy"});
  EXPECT_LT(reason.size(), 400u) << "the quoted line is bounded";
}

TEST(ProcessPlugin, NoOutput) {
  expect_reason(failure_of(shell_plugin("silent", "echo 'forgot to write' >&2\n")),
                {"wrote no AO.exr: forgot to write"});
}

TEST(ProcessPlugin, NotAnImage) {
  expect_reason(failure_of(shell_plugin("text", "echo hello > \"$6\"\n")),
                {"AO.exr is not an image", "(stderr empty)"});
}

TEST(ProcessPlugin, WrongSize) {
  const std::string dir = shell_plugin("small", "cp small.exr \"$6\"\n");
  write_ao(dir, "small.exr", 4, 3, {"AO"}, [](int, int) { return 1.0f; });
  expect_reason(failure_of(dir), {"AO.exr is 4x3, the G-buffer 32x24"});
}

TEST(ProcessPlugin, MissingAOChannel) {
  const std::string dir = shell_plugin("noao", "cp r.exr \"$6\"\n");
  write_ao(dir, "r.exr", 32, 24, {"R"}, [](int, int) { return 1.0f; });
  expect_reason(failure_of(dir), {"AO.exr has no channel AO"});
}

TEST(ProcessPlugin, NaNInACoveredPixelButNotInTheBackground) {
  // NaN on the bottom row (floor) is rejected; NaN on the top row (sky) is ignored.
  const std::string bad = shell_plugin("nan", "cp nan.exr \"$6\"\n");
  write_ao(bad, "nan.exr", 32, 24, {"AO"},
           [](int, int j) { return j == 23 ? std::nanf("") : 1.0f; });
  expect_reason(failure_of(bad), {"AO is NaN at covered pixel (0, 23)"});
  const std::string fine = shell_plugin("skynan", "cp nan.exr \"$6\"\n");
  write_ao(fine, "nan.exr", 32, 24, {"AO"},
           [](int, int j) { return j == 0 ? std::nanf("") : 1.0f; });
  EXPECT_EQ(run_plugin(fine, floor_view()).ao[0], 0.0f);
  const std::string inf = shell_plugin("inf", "cp inf.exr \"$6\"\n");
  write_ao(inf, "inf.exr", 32, 24, {"AO"}, [](int, int) { return INFINITY; });
  expect_reason(failure_of(inf), {"AO is infinite at covered pixel"});
}

TEST(ProcessPlugin, OutOfRangeValuesAreRejectedAndRoundingIsClamped) {
  const std::string bad = shell_plugin("range", "cp over.exr \"$6\"\n");
  write_ao(bad, "over.exr", 32, 24, {"AO"}, [](int, int) { return 1.5f; });
  expect_reason(failure_of(bad), {"AO = 1.5 at covered pixel", "is outside [0, 1]"});
  const std::string negative = shell_plugin("negative", "cp under.exr \"$6\"\n");
  write_ao(negative, "under.exr", 32, 24, {"AO"}, [](int, int) { return -0.01f; });
  expect_reason(failure_of(negative), {"is outside [0, 1]"});
  // Within kAoRangeSlack of the range: float rounding, clamped.
  const GBuffer& g = floor_view().gbuffer;
  for (const float off : {1.0f + 0.5f * kAoRangeSlack, -0.5f * kAoRangeSlack}) {
    const std::string rounding = shell_plugin("rounding", "cp r.exr \"$6\"\n");
    write_ao(rounding, "r.exr", 32, 24, {"AO"}, [off](int, int) { return off; });
    const EstimateResult r = run_plugin(rounding, floor_view());
    EXPECT_EQ(r.ao[g.index(5, 23)], off > 0.5f ? 1.0f : 0.0f);
  }
}

TEST(ProcessPlugin, DeclaredBentNormalsMustBeThere) {
  const fs::path dir = test_temp_dir("process") / "bent";
  make_plugin(dir, R"({"name": "bent", "summary": "s", "kind": "process", "outputs": ["AO", "bent"],
      "command": ["/bin/sh", "plugin.sh"], "definition": {"weighting": "cosine"}})",
              {{"plugin.sh", "cp ao.exr \"$6\"\n"}});
  write_ao(dir.string(), "ao.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  expect_reason(failure_of(dir.string()), {"AO.exr has no channel bent.X"});
  write_ao(dir.string(), "ao.exr", 32, 24, {"AO", "bent.X", "bent.Y", "bent.Z"},
           [](int, int) { return 0.5f; });
  const EstimateResult r = run_plugin(dir.string(), floor_view());
  EXPECT_EQ(r.extra_channels.at("bent.Y")[floor_view().gbuffer.index(0, 23)], 0.5f);
}

TEST(ProcessPlugin, AMalformedTimingFile) {
  const std::string dir = shell_plugin(
      "badtiming", "cp ao_one.exr \"$6\"\necho '{\"frame_ms\": []}' > \"$6.timing.json\"\n");
  write_ao(dir, "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  expect_reason(failure_of(dir), {"frame_ms must be a non-empty array"});
  // Not JSON (NaN), or a number no double holds: the file and the key, not nlohmann's text.
  for (const auto& [text, expected] : std::vector<std::pair<std::string, std::string>>{
           {"{\"frame_ms\": [NaN]}", "AO.exr.timing.json:1:15: invalid JSON (at key frame_ms[0])"},
           {"{\"frame_ms\": [1e400]}",
            "AO.exr.timing.json: invalid JSON at key frame_ms[0]: number overflow parsing "
            "'1e400'"}}) {
    const std::string bad = shell_plugin(
        "badtiming", "cp ao_one.exr \"$6\"\necho '" + text + "' > \"$6.timing.json\"\n");
    write_ao(bad, "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
    const std::string reason = failure_of(bad);
    expect_reason(reason, {expected});
    EXPECT_EQ(reason.find("json.exception"), std::string::npos) << reason;
  }
}

TEST(ProcessPlugin, AStaleOutputFromAnEarlierFrameDoesNotCount) {
  // Frame 1 writes AO.exr; frame 2 writes nothing and must fail, not reuse frame 1's file.
  const std::string dir =
      shell_plugin("once", "if [ -e done ]; then exit 0; fi\ntouch done\ncp ao_one.exr \"$6\"\n");
  write_ao(dir, "ao_one.exr", 32, 24, {"AO"}, [](int, int) { return 1.0f; });
  const EstimatorInfo info = plugin_estimator(read_plugin_manifest(dir));
  auto e = info.create(resolve_params(info.name, info.params, {}, "test"));
  const TestView& v = floor_view();
  const EstimateContext context{v.scene, *v.embree, v.gbuffer};
  e->prepare(context);
  e->run(context);
  EXPECT_THROW(e->run(context), EstimatorUnavailable);
}

}  // namespace
}  // namespace aoeval
