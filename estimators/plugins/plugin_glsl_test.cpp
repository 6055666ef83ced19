// GLSL plug-ins: compile errors name the file and line; SPIR-V is cached by content; the ABI's
// inputs are what the G-buffer holds; a GLSL re-implementation of a built-in's formula agrees with
// it; the shipped alchemy and sao examples give AO = 1 on an open plane and darken a crease.
// Tests that need the Vulkan device skip (with the reason) where there is none.
#include "estimators/plugins/plugin_glsl.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

#include "base/errors.h"
#include "estimators/plugins/plugin_test_util.h"
#include "estimators/registry.h"
#include "estimators/temporal/temporal_stage.h"
#include "estimators/vulkan/vk_context.h"
#include "scenes/corpus.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;
using plugin_test::make_plugin;
using plugin_test::run_plugin;
using testutil::test_temp_dir;

#define REQUIRE_VULKAN()                                                        \
  do {                                                                          \
    std::string why;                                                            \
    if (!vk::shared_context(&why)) GTEST_SKIP() << "no Vulkan device: " << why; \
  } while (0)

// A one-pass GLSL plug-in `name` with `params` (JSON array text) and the body of main().
std::string glsl_plugin(const std::string& name, const std::string& params,
                        const std::string& body) {
  return make_plugin(test_temp_dir("glsl") / name,
                     R"({"name": ")" + name + R"(", "summary": "test", "kind": "glsl",
                         "shaders": ["main.comp"], "params": )" +
                         params + R"(,
                         "definition": {"weighting": "cosine"}})",
                     {{"main.comp",
                       "#version 450\nlayout(local_size_x = 8, local_size_y = 4) in;\n"
                       "void main() {\n  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
                       "  if (!aoeval_inside(p)) return;\n" +
                           body + "\n}\n"}});
}

void use_private_cache() {
  setenv("AOEVAL_CACHE", (test_temp_dir("glsl") / "cache").c_str(), 1);
}

TEST(GlslPlugin, ACompileErrorNamesTheShaderFileAndLine) {
  use_private_cache();
  const std::string dir =
      make_plugin(test_temp_dir("glsl") / "broken",
                  R"({"name": "broken", "summary": "s", "kind": "glsl", "shaders": ["ao.comp"],
          "definition": {"weighting": "cosine"}})",
                  {{"ao.comp",
                    "#version 450\nlayout(local_size_x = 8) in;\nvoid main() {\n  float x = 1.0;\n"
                    "  x += undeclared_thing;\n}\n"}});
  try {
    plugin_estimator(read_plugin_manifest(dir)).create(ParamSet());
    ADD_FAILURE() << "compiled";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(dir + "/ao.comp:5:"), std::string::npos) << what;
    EXPECT_NE(what.find("undeclared_thing"), std::string::npos) << what;
  }
}

TEST(GlslPlugin, SpirvIsCachedByContent) {
  use_private_cache();
  const std::string source =
      "#version 450\nlayout(local_size_x = 4, local_size_y = 2) in;\nvoid main() {}\n";
  const CompiledShader first = compile_glsl_compute("a.comp", source, {});
  const CompiledShader second = compile_glsl_compute("b.comp", source, {});
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(first.spirv, second.spirv);
  EXPECT_EQ(second.local_size[0], 4u);
  EXPECT_EQ(second.local_size[1], 2u);
  // Other parameters change the preamble, so the entry.
  const ParamSpec p = real_param({.name = "r",
                                  .def = 0.5,
                                  .min = 0,
                                  .max = 1,
                                  .spacing = Spacing::linear,
                                  .unit = "",
                                  .meaning = "m"});
  EXPECT_FALSE(compile_glsl_compute("a.comp", source, {p}).from_cache);
  EXPECT_FALSE(compile_glsl_compute("a.comp", source + "\n", {}).from_cache);
}

TEST(GlslPlugin, TheAbiTextDeclaresEveryBindingAndTheParametersInOrder) {
  const std::string text = glsl_abi_text();
  for (int b = 0; b <= 11; ++b)
    EXPECT_NE(text.find("binding = " + std::to_string(b)), std::string::npos) << b;
  const std::vector<ParamSpec> params = {
      real_param({.name = "zeta",
                  .def = 0.5,
                  .min = 0,
                  .max = 1,
                  .spacing = Spacing::linear,
                  .unit = "",
                  .meaning = "m"}),
      bool_param({.name = "alpha", .def = true, .meaning = "m"}),
      choice_param({.name = "mode", .def = "b", .choices = {"a", "b"}, .meaning = "m"})};
  for (const char* name :
       {"aoeval_motion", "aoeval_disoccluded", "aoeval_history", "aoeval_state", "int frame;"})
    EXPECT_NE(text.find(name), std::string::npos) << name;
  const std::string preamble = glsl_abi_preamble(params);
  EXPECT_LT(preamble.find("float zeta;"), preamble.find("bool alpha;"));
  EXPECT_LT(preamble.find("bool alpha;"), preamble.find("int mode;"));
  EXPECT_NE(preamble.find("0 = a, 1 = b"), std::string::npos);
}

// What each ABI input holds, pixel by pixel, against the G-buffer on the CPU.
TEST(GlslPlugin, TheAbiInputsHoldTheGBuffer) {
  REQUIRE_VULKAN();
  use_private_cache();
  const TestView v = crease(40, 30);
  const GBuffer& g = v.gbuffer;
  const std::string dir = glsl_plugin(
      "probe", R"([{"name": "probe", "type": "choice", "default": "depth", "meaning": "m",
                   "choices": ["depth", "normal", "position", "project", "matrix", "unproject"]}])",
      R"(
  const vec4 pos = imageLoad(aoeval_position, p);
  const vec3 n = imageLoad(aoeval_normal, p).xyz;
  const vec2 centre = vec2(p) + 0.5;
  float v = 0.0;
  switch (aoeval.params.probe) {
    case 0: v = imageLoad(aoeval_depth, p).r / 10.0; break;
    case 1: v = 0.5 + 0.5 * n.y; break;
    case 2: v = -pos.z / 10.0; break;
    case 3: v = length(aoeval_project(pos.xyz) - centre); break;
    case 4: {
      const vec4 clip = aoeval.proj * vec4(pos.xyz, 1.0);
      const vec3 ndc = clip.xyz / clip.w;
      const vec4 back = aoeval.inv_proj * clip;
      v = length((ndc.xy * 0.5 + 0.5) * aoeval.size.xy - centre) + abs(ndc.z - 0.01 / -pos.z) +
          length(back.xyz / back.w - pos.xyz);
      break;
    }
    case 5: v = length(aoeval_unproject(centre, -pos.z) - pos.xyz); break;
  }
  imageStore(aoeval_out, p, vec4(aoeval_covered(p) ? clamp(v, 0.0, 1.0) : 0.0));)");
  const Camera& c = g.camera;
  auto probe = [&](const char* which) { return run_plugin(dir, v, {{"probe", which}}).ao; };
  const auto depth = probe("depth"), normal = probe("normal"), position = probe("position");
  const auto project = probe("project"), matrix = probe("matrix"), unproject = probe("unproject");
  size_t covered = 0;
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    if (!g.covered(k)) continue;
    ++covered;
    EXPECT_NEAR(depth[k], g.depth[k] / 10.0f, 1e-6f) << k;
    EXPECT_NEAR(normal[k], 0.5f + 0.5f * glm::dot(g.normal[k], c.up), 1e-6f) << k;
    // -z_eye is the linear depth; the eye-space point projects back to its pixel's centre.
    EXPECT_NEAR(position[k], g.depth[k] / 10.0f, 1e-5f) << k;
    EXPECT_LT(project[k], 2e-3f) << k;
    EXPECT_LT(matrix[k], 2e-3f) << k;
    EXPECT_LT(unproject[k], 1e-4f) << k;
  }
  EXPECT_GT(covered, g.pixel_count() / 2);
}

// outputs "bent": the shader writes eye-space vectors into aoeval_bent, the estimate holds them in
// world space (bent.X/Y/Z). Writing the eye-space normal must give back the G-buffer's normal.
TEST(GlslPlugin, BentNormalsComeBackInWorldSpace) {
  REQUIRE_VULKAN();
  const fs::path dir = test_temp_dir("glsl") / "bent";
  make_plugin(
      dir,
      R"({"name": "bent", "summary": "s", "kind": "glsl", "shaders": ["b.comp"],
                  "outputs": ["AO", "bent"], "definition": {"weighting": "cosine"}})",
      {{"b.comp",
        "#version 450\nlayout(local_size_x = 8, local_size_y = 8) in;\nvoid main() {\n"
        "  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n  if (!aoeval_inside(p)) return;\n"
        "  imageStore(aoeval_bent, p, vec4(imageLoad(aoeval_normal, p).xyz, 0.0));\n"
        "  imageStore(aoeval_out, p, vec4(1.0));\n}\n"}});
  const TestView v = crease(24, 18);
  const EstimateResult r = run_plugin(dir.string(), v);
  size_t covered = 0;
  for (size_t k = 0; k < v.gbuffer.pixel_count(); ++k) {
    if (!v.gbuffer.covered(k)) continue;
    ++covered;
    const glm::vec3 b(r.extra_channels.at("bent.X")[k], r.extra_channels.at("bent.Y")[k],
                      r.extra_channels.at("bent.Z")[k]);
    EXPECT_LT(glm::length(b - v.gbuffer.normal[k]), 1e-5f) << k;
  }
  EXPECT_GT(covered, 0u);
}

TEST(GlslPlugin, PassesRunInOrderAndReadThePreviousOutput) {
  REQUIRE_VULKAN();
  const fs::path dir = test_temp_dir("glsl") / "two";
  const std::string head = "#version 450\nlayout(local_size_x = 8, local_size_y = 8) in;\n";
  make_plugin(
      dir,
      R"({"name": "two", "summary": "s", "kind": "glsl", "shaders": ["first.comp",
                  "second.comp"], "definition": {"weighting": "cosine"}})",
      {{"first.comp", head + "void main() { imageStore(aoeval_out, ivec2(gl_GlobalInvocationID.xy),"
                             " vec4(0.1 * float(aoeval.pass.x + 1))); }\n"},
       {"second.comp", head +
                           "void main() { const ivec2 p = ivec2(gl_GlobalInvocationID.xy);"
                           " imageStore(aoeval_out, p, vec4(2.0 * imageLoad(aoeval_prev, p).r"
                           " + 0.1 * float(aoeval.pass.x) + 0.01 * float(aoeval.pass.y))); }\n"}});
  const TestView v = grazing_floor(16, 12);
  const EstimateResult r = run_plugin(dir.string(), v);
  EXPECT_NEAR(r.ao[v.gbuffer.index(3, 11)], 2.0f * 0.1f + 0.1f + 0.02f, 1e-6f);
  EXPECT_EQ(r.timing_source, "gpu-timestamps");
  EXPECT_TRUE(r.pass_ms.count("first_ms") && r.pass_ms.count("second_ms") &&
              r.pass_ms.count("total_ms"));
}

// Over time (CONTRACT §10, ABI version 2): one instance runs the frames in order. A probe writes
// what each new binding holds; `motion` and `disoccluded` are set here to known patterns.
TEST(GlslPlugin, TheTemporalBindingsHoldTheFrameMotionAndDisocclusion) {
  REQUIRE_VULKAN();
  use_private_cache();
  const std::string dir =
      glsl_plugin("temporal-probe",
                  R"([{"name": "probe", "type": "choice", "default": "frame", "meaning": "m",
           "choices": ["frame", "motion_x", "motion_y", "disoccluded", "seed", "zw"]},
          {"name": "seed", "type": "integer", "default": 5, "min": 0, "max": 1000, "meaning": "m"}])",
                  R"(
  const vec4 m = imageLoad(aoeval_motion, p);
  float v = 0.0;
  switch (aoeval.params.probe) {
    case 0: v = float(aoeval.frame) / 16.0; break;
    case 1: v = 0.5 + m.x / 64.0; break;
    case 2: v = 0.5 + m.y / 64.0; break;
    case 3: v = imageLoad(aoeval_disoccluded, p).r; break;
    case 4: v = float(aoeval.params.seed) / 64.0 + (aoeval.pass.z == aoeval.params.seed ? 0.0 : 0.5); break;
    case 5: v = abs(m.z) + abs(m.w); break;
  }
  imageStore(aoeval_out, p, vec4(clamp(v, 0.0, 1.0)));)");
  const TestView v = grazing_floor(16, 12);
  GBuffer moving = v.gbuffer;
  const size_t n = moving.pixel_count();
  moving.motion.resize(n);
  moving.disoccluded.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const int i = static_cast<int>(k % 16), j = static_cast<int>(k / 16);
    moving.motion[k] =
        glm::vec2(0.75f * static_cast<float>(i % 7 - 3), 1.25f * static_cast<float>(j % 5 - 2));
    moving.disoccluded[k] = (i + j) % 3 == 0 ? 1.0f : 0.0f;
  }
  const EstimatorInfo info = plugin_estimator(read_plugin_manifest(dir));
  EXPECT_TRUE(info.keeps_state);
  for (const char* probe : {"frame", "motion_x", "motion_y", "disoccluded", "seed", "zw"}) {
    auto e = info.create(resolve_params(info.name, info.params, {{"probe", probe}}, "test"));
    for (int f = 0; f < 3; ++f) {
      // The seed rule: frame f runs with seed + offset (offset 0 under seed_per_frame false).
      const uint64_t offset = f == 2 ? 0 : static_cast<uint64_t>(f);
      const FrameInfo frame{.index = f, .count = 3, .fps = 30.0, .seed_offset = offset};
      const EstimateContext context{v.scene, *v.embree, moving, &frame};
      e->prepare(context);
      const EstimateResult r = e->run(context);
      for (size_t k = 0; k < n; ++k) {
        if (!moving.covered(k)) continue;
        const std::string what = std::string(probe) + " frame " + std::to_string(f);
        const std::string p = probe;
        const float expected = p == "frame"         ? static_cast<float>(f) / 16.0f
                               : p == "motion_x"    ? 0.5f + moving.motion[k].x / 64.0f
                               : p == "motion_y"    ? 0.5f + moving.motion[k].y / 64.0f
                               : p == "disoccluded" ? moving.disoccluded[k]
                               : p == "seed"        ? static_cast<float>(5 + offset) / 64.0f
                                                    : 0.0f;
        ASSERT_NEAR(r.ao[k], expected, 1e-6f) << what << " pixel " << k;
      }
    }
  }
  // A still view: frame 0, no motion, nothing disoccluded, the declared seed.
  for (const char* probe : {"frame", "motion_x", "disoccluded", "seed"}) {
    const EstimateResult r = run_plugin(dir, v, {{"probe", probe}});
    const float expected = std::string(probe) == "motion_x" ? 0.5f
                           : std::string(probe) == "seed"   ? 5.0f / 64.0f
                                                            : 0.0f;
    EXPECT_NEAR(r.ao[v.gbuffer.index(3, 11)], expected, 1e-6f) << probe;
  }
}

// aoeval_history is the final pass's output of the previous frame: a second pass that adds 1/8 to
// it counts the frames (the first pass writes 0.9, which history must not see), zero at frame 0,
// on a still view and after a frame that did not run; a repeated frame keeps its history.
TEST(GlslPlugin, HistoryIsThePreviousFramesFinalOutput) {
  REQUIRE_VULKAN();
  use_private_cache();
  const fs::path dir = test_temp_dir("glsl") / "counter";
  const std::string head = "#version 450\nlayout(local_size_x = 8, local_size_y = 8) in;\n";
  make_plugin(
      dir,
      R"({"name": "counter", "summary": "s", "kind": "glsl",
                  "shaders": ["first.comp", "count.comp"], "definition": {"weighting": "cosine"}})",
      {{"first.comp", head + "void main() { imageStore(aoeval_out, "
                             "ivec2(gl_GlobalInvocationID.xy), vec4(0.9)); }\n"},
       {"count.comp", head + "void main() { const ivec2 p = ivec2(gl_GlobalInvocationID.xy);"
                             " imageStore(aoeval_out, p, vec4(min(1.0, "
                             "imageLoad(aoeval_history, p).r + 0.125))); }\n"}});
  const TestView v = grazing_floor(16, 12);
  const size_t px = v.gbuffer.index(3, 11);
  const EstimatorInfo info = plugin_estimator(read_plugin_manifest(dir.string()));
  auto e = info.create(default_params(info));
  auto frame = [&](int k) {
    const FrameInfo f{.index = k, .count = 8, .fps = 30.0, .seed_offset = static_cast<uint64_t>(k)};
    const EstimateContext context{v.scene, *v.embree, v.gbuffer, &f};
    e->prepare(context);
    return e->run(context).ao[px];
  };
  for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(frame(k), 0.125f * static_cast<float>(k + 1)) << k;
  EXPECT_FLOAT_EQ(frame(3), 0.5f) << "a repeated frame 3 reads frame 2's output again";
  EXPECT_FLOAT_EQ(frame(5), 0.125f) << "frame 4 did not run: no history";
  EXPECT_FLOAT_EQ(frame(0), 0.125f) << "frame 0 starts afresh";
  const EstimateContext still{v.scene, *v.embree, v.gbuffer};
  e->prepare(still);
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(e->run(still).ao[px], 0.125f) << "still run " << i;
}

// aoeval_state (ABI version 3): a plug-in keeps its history length L there, unclamped (L reaches
// 12, far outside [0, 1]), and blends alpha = 1 / (L + 1) of each frame's raw value with its
// history: the shared temporal stage's running mean (temporal_stage.h step 4, alpha_min 0, no
// clamp) on a static sequence, frame for frame, and the plain mean of the raw values so far.
// The raw value is an integer hash of (pixel, frame) in 1/256 steps, the same bits on both sides.
// The plug-in computes in float and the stage in double rounded to float each frame: they agree
// to float round-off (a few ulps), not bit for bit. A repeated frame starts from frame k - 1's
// state again, so it repeats its output exactly.
float raw_value(uint32_t x, uint32_t y, uint32_t frame) {
  uint32_t h = (x * 73856093u) ^ (y * 19349663u) ^ (frame * 83492791u);
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return static_cast<float>(h & 255u) / 256.0f;
}

TEST(GlslPlugin, StateKeepsAHistoryLengthForTheStagesRunningMean) {
  REQUIRE_VULKAN();
  use_private_cache();
  const std::string dir = glsl_plugin(
      "running-mean", "[]",
      "  uint h = (uint(p.x) * 73856093u) ^ (uint(p.y) * 19349663u) ^ (uint(aoeval.frame) * "
      "83492791u);\n"
      "  h ^= h >> 13; h *= 0x5bd1e995u; h ^= h >> 15;\n"
      "  const float x = float(h & 255u) / 256.0;\n"
      "  const float L = imageLoad(aoeval_state, p).x;  // frames accumulated here so far\n"
      "  const float alpha = 1.0 / (L + 1.0);\n"
      "  const float ao = alpha * x + (1.0 - alpha) * imageLoad(aoeval_history, p).r;\n"
      "  imageStore(aoeval_state, p, vec4(L + 1.0, 0.0, 0.0, 0.0));\n"
      "  imageStore(aoeval_out, p, vec4(ao));");
  const TestView v = grazing_floor(16, 12);
  const EstimatorInfo info = plugin_estimator(read_plugin_manifest(dir));
  auto e = info.create(default_params(info));
  TemporalSettings stage_settings;
  stage_settings.history_limit = 1000;  // never reached: a pure running mean
  stage_settings.alpha_min = 0.0;
  TemporalAccumulator stage(stage_settings);
  const int frames = 12;
  std::vector<double> sum(v.gbuffer.pixel_count(), 0.0);
  double worst_stage = 0.0, worst_mean = 0.0;
  size_t compared = 0;
  for (int k = 0; k < frames; ++k) {
    const FrameInfo f{.index = k, .count = frames, .fps = 30.0};
    const EstimateContext context{v.scene, *v.embree, v.gbuffer, &f};
    e->prepare(context);
    const std::vector<float> ao = e->run(context).ao;
    EXPECT_EQ(e->run(context).ao, ao) << "a repeated frame " << k << " starts from the same state";
    std::vector<float> raw(v.gbuffer.pixel_count());
    for (int y = 0; y < v.gbuffer.height; ++y)
      for (int x = 0; x < v.gbuffer.width; ++x)
        raw[v.gbuffer.index(x, y)] =
            raw_value(static_cast<uint32_t>(x), static_cast<uint32_t>(y), static_cast<uint32_t>(k));
    stage.accumulate(v.gbuffer, raw);
    for (size_t i = 0; i < raw.size(); ++i) {
      if (!v.gbuffer.covered(i)) continue;
      sum[i] += raw[i];
      ASSERT_EQ(stage.history_length()[i], static_cast<float>(k + 1));
      worst_stage = std::max(worst_stage, std::abs(double(ao[i]) - double(stage.value()[i])));
      worst_mean = std::max(worst_mean, std::abs(double(ao[i]) - sum[i] / (k + 1)));
      ++compared;
    }
  }
  EXPECT_GT(compared, 100u);
  EXPECT_LE(worst_stage, 1e-6) << "the plug-in against the temporal stage";
  EXPECT_LE(worst_mean, 1e-6) << "the plug-in against the mean of the raw values";
  std::printf(
      "aoeval_state running mean over %d frames, %zu pixel-frames: max |plug-in - stage| "
      "= %.3g, max |plug-in - mean| = %.3g\n",
      frames, compared, worst_stage, worst_mean);
}

TEST(GlslPlugin, OutOfRangeOutputIsRejected) {
  REQUIRE_VULKAN();
  const std::string dir = glsl_plugin("two-ish", "[]", "  imageStore(aoeval_out, p, vec4(2.0));");
  const TestView v = grazing_floor(16, 12);
  try {
    run_plugin(dir, v);
    ADD_FAILURE() << "accepted 2";
  } catch (const EstimatorUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("AO = 2 at covered pixel"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(") of frame 0 is outside [0, 1]"), std::string::npos)
        << e.what();  // which frame, for a sequence
  }
}

// The trust test (CONTRACT §7): a GLSL plug-in re-implementing the built-in reeves-blau (Reeves
// and Blau 1985 as Hegeman et al. 2006 describe it: V = exp(-k max(0, R - |P - c|)) on the tree's
// pixels, 1 on every other covered pixel) agrees with the CPU estimator on every covered pixel of
// tree-ground. Why this one: it is a closed form per pixel that needs the world position (so the
// eye-space positions and the inverse view matrix of the ABI), the object id, and six parameters
// whose order in the uniform block matters (a swap changes the answer); the random sampling of
// the screen-space estimators would test a random-number port instead. Tolerance: the world
// position goes through eye space and back in float, |P| ~ 10 scene units, so it differs by
// ~1e-5; k = 2 turns that into < 4e-5 of AO, inside 1e-4.
TEST(GlslPlugin, AgreesWithTheBuiltInReevesBlauOnEveryCoveredPixel) {
  REQUIRE_VULKAN();
  use_private_cache();
  Scene scene = load_scene("tree-ground");
  const View view = scene.views.front();
  const TestView v = render_view(std::move(scene), view, 96, 72);
  const EstimatorInfo& cpu = find_estimator("reeves-blau");
  const ParamSet cpu_params = resolve_params(cpu.name, cpu.params, {{"attenuation", 2.0}}, "test");
  const EstimateContext context{v.scene, *v.embree, v.gbuffer};
  auto estimator = cpu.create(cpu_params);
  estimator->prepare(context);
  const std::vector<float> expected = estimator->run(context).ao;
  const nlohmann::json proxy = estimator->derived()["proxies"][0];
  ASSERT_EQ(proxy["type"], "sphere");
  int object = -1;
  for (size_t i = 0; i < v.scene.objects.size(); ++i)
    if (v.scene.objects[i].name == proxy["object"]) object = static_cast<int>(i);
  const nlohmann::json shape = proxy["shapes"][0];

  const std::string dir = glsl_plugin("reeves-blau-glsl", R"([
      {"name": "tree_object", "type": "integer", "default": 0, "min": 0, "max": 1000, "meaning": "m"},
      {"name": "cx", "type": "real", "default": 0, "min": -1e6, "max": 1e6, "meaning": "m"},
      {"name": "cy", "type": "real", "default": 0, "min": -1e6, "max": 1e6, "meaning": "m"},
      {"name": "cz", "type": "real", "default": 0, "min": -1e6, "max": 1e6, "meaning": "m"},
      {"name": "radius", "type": "real", "default": 1, "min": 0, "max": 1e6, "meaning": "m"},
      {"name": "k", "type": "real", "default": 1, "min": 0, "max": 1e6, "meaning": "m"}])",
                                      R"(
  const vec4 pos = imageLoad(aoeval_position, p);
  float ao = 0.0;
  if (aoeval_covered(p)) {
    ao = 1.0;
    if (int(pos.w) == aoeval.params.tree_object) {
      const vec3 world = (aoeval.inv_view * vec4(pos.xyz, 1.0)).xyz;
      const vec3 c = vec3(aoeval.params.cx, aoeval.params.cy, aoeval.params.cz);
      ao = exp(-aoeval.params.k * max(0.0, aoeval.params.radius - length(world - c)));
    }
  }
  imageStore(aoeval_out, p, vec4(ao));)");
  const std::vector<float> got = run_plugin(dir, v,
                                            {{"tree_object", object},
                                             {"cx", shape["center"][0]},
                                             {"cy", shape["center"][1]},
                                             {"cz", shape["center"][2]},
                                             {"radius", shape["radii"][0]},
                                             {"k", 2.0}})
                                     .ao;
  size_t tree_pixels = 0, covered = 0;
  double worst = 0.0;
  for (size_t k = 0; k < expected.size(); ++k) {
    if (!v.gbuffer.covered(k)) continue;
    ++covered;
    tree_pixels += expected[k] < 1.0f;
    worst = std::max(worst, static_cast<double>(std::abs(got[k] - expected[k])));
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(tree_pixels, covered / 10) << "the view must show the tree";
  EXPECT_LT(tree_pixels, covered) << "and ground";
}

// Alchemy and SAO on an open plane: every v_i lies in the plane, v_i . n = 0, so each estimator's
// sum is 0 and A = 1 exactly (up to float rounding of v . n).
TEST(GlslPlugin, ShippedAlchemyAndSaoSeeAnOpenPlaneAsOpen) {
  REQUIRE_VULKAN();
  const TestView v = grazing_floor(64, 48);
  for (const char* name : {"alchemy", "sao"}) {
    const EstimatorInfo& info = find_estimator(name);
    auto e = info.create(resolve_params(name, info.params, {}, "test"));
    const EstimateContext context{v.scene, *v.embree, v.gbuffer};
    e->prepare(context);
    const std::vector<float> ao = e->run(context).ao;
    for (size_t k = 0; k < ao.size(); ++k) {
      if (v.gbuffer.covered(k)) {
        ASSERT_NEAR(ao[k], 1.0f, 1e-4f) << name << " pixel " << k;
      }
    }
  }
}

// In the crease (a floor meeting a wall) both darken the pixels next to the corner line and leave
// the pixels far from it open; every value is in [0, 1].
TEST(GlslPlugin, ShippedAlchemyAndSaoDarkenACrease) {
  REQUIRE_VULKAN();
  const TestView v = crease(80, 60);
  const GBuffer& g = v.gbuffer;
  for (const char* name : {"alchemy", "sao"}) {
    const EstimatorInfo& info = find_estimator(name);
    auto e = info.create(resolve_params(name, info.params, {{"radius", 0.5}}, "test"));
    const EstimateContext context{v.scene, *v.embree, v.gbuffer};
    e->prepare(context);
    const std::vector<float> ao = e->run(context).ao;
    double near_sum = 0, far_sum = 0;
    int near_n = 0, far_n = 0;
    for (size_t k = 0; k < ao.size(); ++k) {
      if (!g.covered(k)) continue;
      ASSERT_GE(ao[k], 0.0f);
      ASSERT_LE(ao[k], 1.0f);
      // Distance to the corner line y = 0, z = -2.
      const float d = std::hypot(g.position[k].y, g.position[k].z + 2.0f);
      if (d < 0.1f) near_sum += ao[k], ++near_n;
      if (d > 1.0f) far_sum += ao[k], ++far_n;
    }
    ASSERT_GT(near_n, 0);
    ASSERT_GT(far_n, 0);
    EXPECT_LT(near_sum / near_n, 0.9) << name;
    EXPECT_GT(far_sum / far_n, 0.97) << name;
  }
}

// Alchemy's second pass (alchemy_blur.comp) removes the noise tile's per-pixel pattern from the
// raw estimate without moving its level: in the crease, the mean squared difference between
// horizontally adjacent covered pixels falls to under half of the raw estimate's, the mean AO moves
// by under 0.02, background pixels stay 0 and blur_radius 0 is the raw estimate itself.
TEST(GlslPlugin, ShippedAlchemysBlurSmoothsTheNoiseAndKeepsTheLevel) {
  REQUIRE_VULKAN();
  const TestView v = crease(80, 60);
  const GBuffer& g = v.gbuffer;
  const EstimatorInfo& info = find_estimator("alchemy");
  const auto run_with = [&](int blur_radius) {
    auto e = info.create(resolve_params("alchemy", info.params,
                                        {{"radius", 0.5}, {"blur_radius", blur_radius}}, "test"));
    const EstimateContext context{v.scene, *v.embree, v.gbuffer};
    e->prepare(context);
    return e->run(context).ao;
  };
  const std::vector<float> raw = run_with(0), blurred = run_with(3);
  const auto roughness = [&](const std::vector<float>& ao) {
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < g.height; ++y) {
      for (int x = 0; x + 1 < g.width; ++x) {
        const size_t k = static_cast<size_t>(y) * g.width + x;
        if (!g.covered(k) || !g.covered(k + 1)) continue;
        sum += (ao[k + 1] - ao[k]) * (ao[k + 1] - ao[k]);
        ++n;
      }
    }
    return sum / n;
  };
  const auto mean = [&](const std::vector<float>& ao) {
    double sum = 0.0;
    int n = 0;
    for (size_t k = 0; k < ao.size(); ++k) {
      if (g.covered(k)) sum += ao[k], ++n;
    }
    return sum / n;
  };
  EXPECT_GT(roughness(raw), 0.0) << "the raw estimate must carry the noise tile's pattern";
  EXPECT_LT(roughness(blurred), 0.5 * roughness(raw));
  EXPECT_NEAR(mean(blurred), mean(raw), 0.02);
  for (size_t k = 0; k < blurred.size(); ++k) {
    if (!g.covered(k)) {
      ASSERT_EQ(blurred[k], 0.0f) << k;
    }
  }
}

// lavapipe's loop cap (65,535 iterations per loop and invocation): what a shader's SPIR-V shows of
// it is found, and the row warns on lavapipe; a bound that is computed is not seen.
TEST(GlslPlugin, LoopsThatLavapipeCutsShortAreWarnedAbout) {
  use_private_cache();
  const std::string head =
      "#version 450\nlayout(local_size_x = 8) in;\nvoid main() {\n  float a = 0.0;\n";
  const std::string tail = "  imageStore(aoeval_out, ivec2(0), vec4(fract(a)));\n}\n";
  auto risks = [&](const std::string& body) {
    return lavapipe_loop_risks(compile_glsl_compute("loop.comp", head + body + tail, {}).spirv);
  };
  EXPECT_EQ(risks("  for (int i = 0; i < 100000; ++i) a += 0.5;\n"),
            std::vector<std::string>{"a loop bound of 100000"});
  EXPECT_EQ(risks("  for (uint i = 0u; i < 70000u; ++i) a += 0.5;\n"),
            std::vector<std::string>{"a loop bound of 70000"});
  EXPECT_EQ(risks("  while (true) { a += 0.5; if (a > 1e30) break; }\n"),
            std::vector<std::string>{"an endless loop (left by a break, if at all)"});
  EXPECT_EQ(risks("  while (true) a += 0.5;\n"),
            std::vector<std::string>{"an endless loop (left by a break, if at all)"});
  EXPECT_EQ(risks("  for (;;) { a += 0.5; }\n"),
            std::vector<std::string>{"an endless loop (left by a break, if at all)"});
  EXPECT_EQ(risks("  for (int i = 0; i < 65535; ++i) { if (a > 3.0) break; a += 0.5; }\n"),
            std::vector<std::string>{});
  EXPECT_EQ(risks("  int i = 0;\n  do { a += 0.5; } while (++i < 10);\n"),
            std::vector<std::string>{});
  EXPECT_EQ(risks("  for (int i = 0; i < 65535; ++i) a += 0.5;\n"), std::vector<std::string>{});
  EXPECT_EQ(risks("  if (a < 100000.0) a = 1.0;\n"), std::vector<std::string>{});  // no loop
  REQUIRE_VULKAN();
  const std::string dir = glsl_plugin(
      "long-loop", R"([{"name": "n", "type": "integer", "default": 10, "min": 1, "max": 1000000,
                       "meaning": "iterations"}])",
      "  float a = 0.0;\n  for (int i = 0; i < aoeval.params.n; ++i) a += 1.0;\n"
      "  imageStore(aoeval_out, p, vec4(a / float(aoeval.params.n)));");
  const EstimatorInfo info = plugin_estimator(read_plugin_manifest(dir));
  const TestView v = grazing_floor(16, 12);
  const EstimateContext context{v.scene, *v.embree, v.gbuffer};
  for (const int64_t n : {int64_t{10}, int64_t{100000}}) {
    auto e = info.create(resolve_params(info.name, info.params, {{"n", n}}, "test"));
    e->prepare(context);
    const EstimateResult r = e->run(context);
    const bool lavapipe = vk::shared_context()->device_name().find("llvmpipe") != std::string::npos;
    if (n == 10 || !lavapipe) {
      EXPECT_FALSE(e->derived().contains("warning")) << e->derived();
      continue;
    }
    EXPECT_EQ(e->derived().value("warning", ""),
              "lavapipe ends loops after 65535 iterations per invocation (all loops together), "
              "and this shader may need more (parameter n = 100000)");
    // And it does cut it: the loop stopped at the cap, AO = 65535 / 100000.
    EXPECT_NEAR(r.ao[v.gbuffer.index(3, 11)], 65535.0f / 100000.0f, 1e-6f);
  }
}

// Must-show 3 of issue 28: a shader that would run for a minute with timeout_s 1 is a skipped
// frame within seconds, and the next plug-in runs on a new device and gets its right answer.
// lavapipe stops an invocation's loops after 65,535 iterations in all, so the work is in the body:
// 65,535 iterations of 1,024 dependent steps on each of 64 x 48 pixels. Last in this file: the
// abandoned shader keeps the old device's threads busy until it ends or the process exits.
TEST(GlslPlugin, AShaderPastItsTimeoutIsSkippedAndTheNextRunsOnANewDevice) {
  REQUIRE_VULKAN();
  use_private_cache();
  const std::string dir =
      make_plugin(test_temp_dir("glsl") / "forever",
                  R"({"name": "forever", "summary": "s", "kind": "glsl", "shaders": ["ao.comp"],
          "timeout_s": 1, "definition": {"weighting": "cosine"}})",
                  {{"ao.comp",
                    "#version 450\nlayout(local_size_x = 8, local_size_y = 4) in;\n"
                    "#define R4(x) x x x x\n"
                    "void main() {\n"
                    "  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
                    "  float a = imageLoad(aoeval_depth, p).r;\n"
                    "  for (int i = 0; i < 65000; ++i) {\n"
                    "    R4(R4(R4(R4(R4(a = fract(a * 1.0001 + 0.37);)))))\n"
                    "  }\n"
                    "  imageStore(aoeval_out, p, vec4(clamp(a, 0.0, 1.0)));\n}\n"}});
  const TestView v = grazing_floor(64, 48);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run_plugin(dir, v);
    ADD_FAILURE() << "finished";
  } catch (const EstimatorUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("plug-in forever timed out after 1 s"), std::string::npos)
        << e.what();
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(s, 20.0) << "the time-out (1 s), compilation and the upload";
  const std::string next =
      glsl_plugin("after-timeout", "[]", "  imageStore(aoeval_out, p, vec4(0.25));");
  const EstimateResult r = run_plugin(next, v);
  EXPECT_EQ(r.ao[v.gbuffer.index(3, 11)], 0.25f);
}

}  // namespace
}  // namespace aoeval
