// "protocol": "frames" process plug-ins (plugin_frames.h, CONTRACT §10): the happy path (one
// program for all frames, the requests, the seed rule, timing, EOF), and one test per way the
// program can break the protocol, each by a tiny Python plug-in written here (standard library
// only: it starts in tens of milliseconds). Every failure must be an EstimatorUnavailable naming
// what went wrong and quoting the last stderr line, and leave no process and no file behind.
#include "estimators/plugins/plugin_frames.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "estimators/plugins/plugin_test_util.h"
#include "scenes/exr_io.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;
using plugin_test::make_plugin;
using testutil::test_temp_dir;

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

// An AO EXR of `value` everywhere, the floor view's size, at `path`.
void write_constant_ao(const fs::path& path, float value) {
  OIIO::ImageSpec spec(32, 24, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO"};
  OIIO::ImageBuf image(spec);
  auto* px = static_cast<float*>(image.localpixels());
  std::fill(px, px + 32 * 24, value);
  ASSERT_TRUE(image.write(path.string()));
}

// A frames plug-in `name` whose Python program runs `body` for each request (r: the request, k:
// its frame) before copying ao.exr (0.5 everywhere) to r["out"] and answering ok.
std::string frames_plugin(const std::string& name, const std::string& body,
                          double timeout_s = 20.0) {
  const fs::path dir = test_temp_dir("frames") / name;
  make_plugin(dir,
              R"({"name": ")" + name + R"(", "summary": "test", "kind": "process",
                  "protocol": "frames", "command": ["/usr/bin/python3", "plugin.py"],
                  "timeout_s": )" +
                  format_param_value(timeout_s) +
                  R"(, "definition": {"weighting": "cosine"},
                  "params": [{"name": "seed", "type": "integer", "default": 40, "min": 0,
                              "max": 1000, "meaning": "m"}]})",
              {{"plugin.py",
                "import json, os, shutil, signal, subprocess, sys, time\n"
                "with open('starts.txt', 'a') as f: f.write('%d\\n' % os.getpid())\n"
                "for line in sys.stdin:\n"
                "    r = json.loads(line)\n"
                "    k = r['frame']\n" +
                    body +
                    "\n"
                    "    shutil.copy('ao.exr', r['out'])\n"
                    "    print(json.dumps({'frame': k, 'ok': True}), flush=True)\n"
                    "with open('eof.txt', 'w') as f: f.write('eof')\n"}});
  write_constant_ao(dir / "ao.exr", 0.5f);
  return dir.string();
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path private_tmp() {
  const fs::path tmp = test_temp_dir("frames") / "tmp";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  setenv("TMPDIR", tmp.c_str(), 1);
  return tmp;
}

std::unique_ptr<Estimator> create(const std::string& folder, nlohmann::json overrides = {}) {
  const EstimatorInfo info = plugin_estimator(read_plugin_manifest(folder));
  EXPECT_TRUE(info.keeps_state);
  return info.create(resolve_params(
      info.name, info.params, overrides.is_null() ? nlohmann::json::object() : overrides, "test"));
}

EstimateResult run_frame(Estimator& e, int k, uint64_t seed_offset) {
  const TestView& v = floor_view();
  const FrameInfo info{.index = k, .count = 8, .fps = 30.0, .seed_offset = seed_offset};
  const EstimateContext context{v.scene, *v.embree, v.gbuffer, &info};
  e.prepare(context);
  return e.run(context);
}

// The children of this process (zombies included): none may be left by a plug-in.
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

// Runs frames 0..frames-1 on one instance; the reason of the first failure ("" if none). The
// instance is destroyed before returning: no file and no process may be left.
std::string failure_of(const std::string& folder, int frames = 1) {
  const fs::path tmp = private_tmp();
  std::string reason;
  {
    auto e = create(folder);
    try {
      for (int k = 0; k < frames; ++k) run_frame(*e, k, static_cast<uint64_t>(k));
    } catch (const EstimatorUnavailable& u) {
      reason = u.what();
    }
  }
  EXPECT_TRUE(fs::is_empty(tmp)) << "files left in " << tmp;
  EXPECT_EQ(children_of_this_process(), std::vector<std::string>{}) << "processes left";
  return reason;
}

void expect_reason(const std::string& reason, const std::vector<std::string>& parts) {
  EXPECT_FALSE(reason.empty()) << "the plug-in did not fail";
  for (const auto& p : parts)
    EXPECT_NE(reason.find(p), std::string::npos) << p << " in: " << reason;
}

// One program for the sequence: it sees each frame's request with the frame's files (P.json under
// the seed rule: seed + k), answers, and exits by itself at EOF when the instance ends.
TEST(FramesProtocol, OneProgramAnswersEveryFrameInOrderAndExitsAtEof) {
  const std::string dir = frames_plugin("happy", R"(
    shutil.copy(r['params'], 'params-%d.json' % k)
    assert os.path.isabs(r['gbuffer']) and os.path.getsize(r['gbuffer']) > 0
    with open('requests.txt', 'a') as f: f.write(' '.join(sorted(r)) + ' %d\n' % k)
    if k == 2:
        with open(r['out'] + '.timing.json', 'w') as f: json.dump({'frame_ms': [7.5]}, f))");
  for (const char* f : {"starts.txt", "requests.txt", "eof.txt"}) fs::remove(fs::path(dir) / f);
  const fs::path tmp = private_tmp();
  {
    auto e = create(dir);
    for (int k = 0; k < 4; ++k) {
      const EstimateResult r = run_frame(*e, k, static_cast<uint64_t>(k));
      const GBuffer& g = floor_view().gbuffer;
      EXPECT_EQ(r.ao[g.index(3, 23)], 0.5f) << k;
      EXPECT_EQ(r.ao[g.index(3, 0)], 0.0f) << "sky";
      EXPECT_EQ(r.timing_source, k == 2 ? "plugin-frames" : "frame-wall") << k;
      if (k == 2) {
        EXPECT_EQ(r.pass_ms.at("total_ms"), 7.5);
      }
      EXPECT_GT(r.pass_ms.at("process_ms"), 0.0);
      std::ifstream in(fs::path(dir) / ("params-" + std::to_string(k) + ".json"));
      EXPECT_EQ(nlohmann::json::parse(in), (nlohmann::json{{"seed", 40 + k}})) << k;
    }
    EXPECT_FALSE(fs::exists(fs::path(dir) / "eof.txt")) << "still running between frames";
  }
  EXPECT_EQ(read_text(fs::path(dir) / "requests.txt"),
            "frame gbuffer out params 0\nframe gbuffer out params 1\n"
            "frame gbuffer out params 2\nframe gbuffer out params 3\n");
  const std::string starts = read_text(fs::path(dir) / "starts.txt");
  EXPECT_EQ(std::count(starts.begin(), starts.end(), '\n'), 1) << "started once for the sequence";
  EXPECT_EQ(read_text(fs::path(dir) / "eof.txt"), "eof") << "EOF on stdin: it exited by itself";
  EXPECT_TRUE(fs::is_empty(tmp));
  EXPECT_EQ(children_of_this_process(), std::vector<std::string>{});
}

// A still view (no FrameInfo): frame 0 each run, the same program, the seed unchanged.
TEST(FramesProtocol, AStillViewIsFrameZeroOfOneProgram) {
  const std::string dir = frames_plugin("still", "    shutil.copy(r['params'], 'seen.json')");
  fs::remove(fs::path(dir) / "starts.txt");
  {
    auto e = create(dir, {{"seed", 3}});
    const TestView& v = floor_view();
    const EstimateContext context{v.scene, *v.embree, v.gbuffer};
    e->prepare(context);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(e->run(context).ao.back(), 0.5f);
  }
  std::ifstream in(fs::path(dir) / "seen.json");
  EXPECT_EQ(nlohmann::json::parse(in), (nlohmann::json{{"seed", 3}}));
  const std::string starts = read_text(fs::path(dir) / "starts.txt");
  EXPECT_EQ(std::count(starts.begin(), starts.end(), '\n'), 1) << "started once";
}

TEST(FramesProtocol, GarbageOnStdoutIsQuoted) {
  expect_reason(failure_of(frames_plugin("garbage", "    print('loading model...', flush=True)")),
                {"plug-in garbage answered frame 0 with 'loading model...', not a JSON line "
                 "{\"frame\": 0, \"ok\": true}"});
}

TEST(FramesProtocol, AWrongFrameNumber) {
  expect_reason(failure_of(frames_plugin("wrongframe",
                                         "    if k == 1:\n"
                                         "        print(json.dumps({'frame': 7, 'ok': True}), "
                                         "flush=True)\n        continue"),
                           3),
                {"plug-in wrongframe answered frame 7 to frame 1"});
}

TEST(FramesProtocol, AnErrorItReportsIsQuotedWithItsStderr) {
  expect_reason(failure_of(frames_plugin("reports",
                                         "    print('no GPU here', file=sys.stderr, flush=True)\n"
                                         "    print(json.dumps({'frame': k, 'error': 'no GPU'}), "
                                         "flush=True)\n    continue")),
                {"plug-in reports reported an error on frame 0: 'no GPU': no GPU here"});
}

// An error that is not a string is quoted as its JSON (it gave an empty reason), and an answer
// line with control bytes in it (NULs after the JSON, which the parser ignored) is refused.
TEST(FramesProtocol, AnErrorObjectIsQuotedAndControlBytesAreRefused) {
  expect_reason(failure_of(frames_plugin("errobject",
                                         "    print(json.dumps({'frame': k, 'error': {'x': 1}}), "
                                         "flush=True)\n    continue")),
                {"plug-in errobject reported an error on frame 0: '{\"x\":1}'"});
  expect_reason(
      failure_of(frames_plugin("nul",
                               "    shutil.copy('ao.exr', r['out'])\n"
                               "    sys.stdout.write(json.dumps({'frame': k, 'ok': True}) + "
                               "'\\0\\0\\n')\n    sys.stdout.flush()\n    continue")),
      {"plug-in nul answered frame 0 with '{\"frame\": 0, \"ok\": true}?\?', which holds a "
       "control byte (NUL), not a JSON line"});
}

TEST(FramesProtocol, ACrashMidSequence) {
  expect_reason(failure_of(frames_plugin("crash",
                                         "    if k == 2:\n"
                                         "        print('about to crash', file=sys.stderr, "
                                         "flush=True)\n"
                                         "        os.kill(os.getpid(), signal.SIGSEGV)"),
                           4),
                {"plug-in crash killed by signal 11 (SEGV) before answering frame 2: about to "
                 "crash"});
}

TEST(FramesProtocol, AnExitBeforeAnswering) {
  expect_reason(failure_of(frames_plugin("quits", "    if k == 1: sys.exit(0)"), 3),
                {"plug-in quits exited (status 0) before answering frame 1"});
  expect_reason(failure_of(frames_plugin("fails", "    sys.exit('cannot go on')")),
                {"exited with status 1 before answering frame 0: cannot go on"});
}

// The time-out is per frame: the first frames answer, the slow one is killed with its process
// group and a setsid grandchild, well before the frame would have ended.
TEST(FramesProtocol, ATimeOutPerFrameKillsEverything) {
  const std::string marker = "3600.7" + std::to_string(getpid() % 1000);
  const std::string dir = frames_plugin("slow",
                                        "    if k == 2:\n"
                                        "        subprocess.Popen(['setsid', 'sleep', '" +
                                            marker +
                                            "'])\n"
                                            "        print('still thinking', file=sys.stderr, "
                                            "flush=True)\n"
                                            "        time.sleep(30)",
                                        /*timeout_s=*/1.0);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string reason = failure_of(dir, 4);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  expect_reason(reason, {"timed out after 1 s on frame 2 (process group killed): still thinking"});
  // The slow frame would take 30 s; the bound leaves room for a loaded machine's python start-up.
  EXPECT_LT(s, 15.0) << "three quick frames and the time-out (1 s), well short of the 30 s sleep";
  bool survived = false;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    std::ifstream in(entry.path() / "cmdline");
    std::string cmdline((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (cmdline.find(marker) != std::string::npos) survived = true;
  }
  EXPECT_FALSE(survived) << "the setsid grandchild survived";
}

// The stray line comes in the answer's own write (one os.write), so it is waiting when the next
// frame starts: written separately it could arrive after the next request and be read as that
// frame's answer (a different, also correct, failure; the test failed that way 2 times in 12).
TEST(FramesProtocol, OutputBetweenFramesAndOverlongLines) {
  expect_reason(failure_of(frames_plugin("chatty",
                                         "    shutil.copy('ao.exr', r['out'])\n"
                                         "    os.write(1, (json.dumps({'frame': k, 'ok': True}) + "
                                         "'\\ndone\\n').encode())\n    continue"),
                           2),
                {"wrote 'done' to stdout between frames"});
  expect_reason(failure_of(frames_plugin("long", "    print('x' * 100000, flush=True)")),
                {"answered frame 0 with a line longer than 64 KiB"});
}

// The per-run protocol's output checks hold for each frame.
TEST(FramesProtocol, ABadOutputNamesTheFrame) {
  expect_reason(failure_of(frames_plugin("noout",
                                         "    if k == 1:\n"
                                         "        print(json.dumps({'frame': k, 'ok': True}), "
                                         "flush=True)\n        continue"),
                           2),
                {"plug-in noout wrote no AO.exr (frame 1)"});
}

TEST(FramesProtocol, TheManifestKeyIsChecked) {
  auto error_of = [](const std::string& extra, const std::string& kind = "process") {
    const fs::path dir = test_temp_dir("frames") / "manifest";
    make_plugin(dir,
                R"({"name": "m", "summary": "s", "kind": ")" + kind + R"(", )" + extra +
                    R"(, "definition": {"weighting": "cosine"}})",
                {{"a.comp", "#version 450\nvoid main() {}\n"}});
    try {
      read_plugin_manifest(dir.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string command = R"("command": ["sh", "-c", "true"])";
  expect_reason(error_of(command + R"(, "protocol": "stream")"),
                {"estimator.json: protocol: \"stream\" is not run (once per frame, the default) "
                 "or frames"});
  expect_reason(error_of(command + R"(, "protocol": 3)"), {"protocol: expected a string"});
  expect_reason(error_of(command + R"(, "protocol": "frames", "frames": 3)"),
                {"frames: only for \"protocol\": \"run\""});
  expect_reason(error_of(R"("shaders": ["a.comp"], "protocol": "frames")", "glsl"),
                {"protocol: only for kind process"});
  EXPECT_EQ(error_of(command + R"(, "protocol": "run")"), "");
  EXPECT_EQ(error_of(command + R"(, "protocol": "frames")"), "");
}

}  // namespace
}  // namespace aoeval

namespace aoeval {
namespace {

bool same_params(const std::vector<ParamSpec>& a, const std::vector<ParamSpec>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].name != b[i].name || a[i].type != b[i].type ||
        a[i].default_value != b[i].default_value || a[i].min != b[i].min || a[i].max != b[i].max ||
        a[i].log_scale != b[i].log_scale || a[i].unit != b[i].unit ||
        a[i].meaning != b[i].meaning || a[i].choices != b[i].choices)
      return false;
  return true;
}

// The shipped crytek-ssao-frames is crytek-ssao's program under the frames protocol: the same
// declaration but for name and protocol, and the same AO bit for bit, frame k under the frames
// protocol (seed + k applied by aoeval) against the per-run protocol given seed + k.
TEST(FramesProtocol, TheFramesExampleIsCrytekSsao) {
  const std::string shipped = shipped_plugins_dir();
  const PluginManifest run = read_plugin_manifest(shipped + "/crytek-ssao");
  const PluginManifest frames = read_plugin_manifest(shipped + "/crytek-ssao-frames");
  EXPECT_EQ(run.protocol, ProcessProtocol::run);
  EXPECT_EQ(frames.protocol, ProcessProtocol::frames);
  EXPECT_TRUE(same_params(run.params, frames.params));
  EXPECT_EQ(plugin_definition_doc(run), plugin_definition_doc(frames));
  EXPECT_EQ(run.open_plane_tolerance, frames.open_plane_tolerance);
  EXPECT_EQ(run.timeout_s, frames.timeout_s);
  EXPECT_EQ(run.bent, frames.bent);
  const EstimatorInfo run_info = plugin_estimator(run), frames_info = plugin_estimator(frames);
  EXPECT_FALSE(run_info.keeps_state);
  auto persistent = frames_info.create(default_params(frames_info));
  const TestView& v = floor_view();
  std::vector<std::vector<float>> seen;
  for (int k = 0; k < 2; ++k) {
    const EstimateResult a = run_frame(*persistent, k, static_cast<uint64_t>(k));
    seen.push_back(a.ao);
    auto once = run_info.create(resolve_params(run.name, run.params, {{"seed", 7 + k}}, "test"));
    const EstimateContext context{v.scene, *v.embree, v.gbuffer};
    once->prepare(context);
    const EstimateResult b = once->run(context);
    EXPECT_EQ(a.ao, b.ao) << "frame " << k;
    EXPECT_EQ(a.timing_source, "plugin-frames");
  }
  EXPECT_NE(seen[0], seen[1]) << "frame 1's seed (8) gives other sample offsets than frame 0's";
}

}  // namespace
}  // namespace aoeval
