// GLSL plug-ins: run-time compilation (glslang), the ABI, and the passes on the Vulkan layer.
#include "estimators/plugins/plugin_glsl.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <glslang/build_info.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "base/errors.h"
#include "base/hash.h"
#include "estimators/plugins/plugin_process.h"
#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_context.h"
#include "estimators/vulkan/vk_pipelines.h"
#include "estimators/vulkan/vk_resources.h"
#include "scenes/exr_io.h"
#include "scenes/random.h"
#include "scenes/scene.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

constexpr int kNoiseSize = 64;       // the noise tile is kNoiseSize x kNoiseSize texels
constexpr float kNearPlane = 0.01f;  // of the reversed-Z projection, scene units

// The binding table of the ABI; the preamble below declares the same, in this order.
const std::vector<VkDescriptorType> kBindings = {
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 0 aoeval_depth
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 1 aoeval_normal
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 2 aoeval_position
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 3 aoeval_prev
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 4 aoeval_out
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 5 aoeval_bent
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 6 aoeval_noise
    VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,  // 7 the aoeval block
    // Version 2, over time (CONTRACT §10); version 1's bindings above never move.
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,  // 8 aoeval_motion
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,  // 9 aoeval_disoccluded
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,  // 10 aoeval_history
};

const char* kFixedPreamble =
    R"(// ---- aoeval GLSL plug-in ABI, version 2 (aoeval estimators abi) ----
// Every image is width x height unless noted; pixel (i, j) has its centre at (i + 0.5, j + 0.5), row
// 0 at the top. Eye space: right-handed, x right, y up, the camera looking down -z.
layout(set = 0, binding = 0, r32f) uniform readonly image2D aoeval_depth;       // linear depth Z = -z_eye > 0; 0 where not covered
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D aoeval_normal;   // xyz: unit eye-space shading normal, facing the viewer; w: coverage A (1 surface, 0 background)
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D aoeval_position; // xyz: eye-space position; w: objectId (-1 background)
layout(set = 0, binding = 3, r32f) uniform readonly image2D aoeval_prev;        // the previous pass's aoeval_out (pass 0: zeros)
layout(set = 0, binding = 4, r32f) uniform writeonly image2D aoeval_out;        // this pass's output; the last pass's is the AO, in [0, 1]
layout(set = 0, binding = 5, rgba32f) uniform image2D aoeval_bent;              // xyz: eye-space bent normal (outputs "bent": cleared to zero at the start of each frame, read back and turned to world space)
layout(set = 0, binding = 6, rgba32f) uniform readonly image2D aoeval_noise;    // 64 x 64 tile of uniform random numbers in [0, 1), from aoeval.pass.z
// Over time (version 2; CONTRACT §10). On a still view and at frame 0 all three hold zeros.
layout(set = 0, binding = 8, rgba32f) uniform readonly image2D aoeval_motion;   // xy: motion.X/Y in pixels, this pixel's surface point was at its centre - xy in the previous frame; zw: 0; 0 where not covered
layout(set = 0, binding = 9, r32f) uniform readonly image2D aoeval_disoccluded; // 1 where this pixel's point was not visible in the previous frame (off screen, hidden, another object), else 0
layout(set = 0, binding = 10, r32f) uniform readonly image2D aoeval_history;    // this plug-in's own final output (the last pass's aoeval_out, as written) of the previous frame
struct AoevalParams {
)";

const char* kFixedBlock = R"(};
layout(std140, set = 0, binding = 7) uniform AoevalFrame {
  mat4 proj;         // eye -> clip, Vulkan conventions: y down, reversed-Z depth near / -z_eye, near 0.01, far infinite
  mat4 inv_proj;     // clip -> eye
  mat4 view;         // world -> eye
  mat4 inv_view;     // eye -> world
  vec4 eye_world;    // camera position, world space (w = 1)
  vec4 size;         // width, height, 1 / width, 1 / height (pixels)
  vec4 lens;         // focal length f in pixels (= height / (2 tan(fov_y / 2))), tan(fov_x / 2), tan(fov_y / 2), aspect
  ivec4 pass;        // this pass's index, the number of passes, the noise seed (parameter "seed" when declared, + frame under the seed rule, else 0), the noise tile size (64)
  int frame;         // the frame index k in the sequence (0 on a still view)
  AoevalParams params;  // the manifest's parameters, in manifest order
} aoeval;
// Continuous pixel coordinates of an eye-space point (pixel centres at i + 0.5).
vec2 aoeval_project(vec3 p) {
  return vec2(0.5 * aoeval.size.x + aoeval.lens.x * p.x / -p.z,
              0.5 * aoeval.size.y - aoeval.lens.x * p.y / -p.z);
}
// The eye-space point at continuous pixel coordinates `px` and linear depth z (the inverse).
vec3 aoeval_unproject(vec2 px, float z) {
  return vec3((px.x - 0.5 * aoeval.size.x) * z / aoeval.lens.x,
              (0.5 * aoeval.size.y - px.y) * z / aoeval.lens.x, -z);
}
bool aoeval_inside(ivec2 p) { return all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, ivec2(aoeval.size.xy))); }
bool aoeval_covered(ivec2 p) { return aoeval_inside(p) && imageLoad(aoeval_normal, p).w > 0.5; }
// ---- end of the aoeval ABI ----
)";

const char* glsl_type_of(ParamType t) {
  switch (t) {
    case ParamType::real:
      return "float";
    case ParamType::integer:
      return "int";
    case ParamType::boolean:
      return "bool";
    case ParamType::choice:
      return "int";
  }
  return "float";
}

std::string hex64(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// OpExecutionMode %main LocalSize x y z: the work-group size the dispatch needs.
bool local_size_of(const std::vector<uint32_t>& words, uint32_t out[3]) {
  for (size_t i = 5; i < words.size();) {
    const uint32_t count = words[i] >> 16, opcode = words[i] & 0xffffu;
    if (count == 0 || i + count > words.size()) return false;
    if (opcode == 16 && count >= 6 && words[i + 2] == 17) {  // OpExecutionMode, LocalSize
      for (int d = 0; d < 3; ++d) out[d] = words[i + 3 + static_cast<size_t>(d)];
      return true;
    }
    i += count;
  }
  return false;
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// glslang's log: "ERROR: /path/ao.comp:12: 'x' : undeclared identifier" -> the first error line
// without its prefix. Errors in the preamble are named by the string glslang gives it.
std::string first_error(const std::string& log, const std::string& file) {
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("ERROR: ", 0) != 0) continue;
    line = line.substr(7);
    if (line.find(file) == std::string::npos)
      return file + ": in aoeval's ABI preamble (check the parameter names): " + line;
    return line;
  }
  return file + ": " + log;
}

std::mutex& glslang_mutex() {
  static std::mutex m;
  return m;
}

}  // namespace

std::string glsl_abi_preamble(const std::vector<ParamSpec>& params) {
  std::string text = kFixedPreamble;
  if (params.empty()) text += "  int aoeval_no_parameters;  // (a plug-in without parameters)\n";
  for (const auto& p : params) {
    text += "  " + std::string(glsl_type_of(p.type)) + " " + p.name + ";  // " + p.meaning;
    if (p.type == ParamType::choice) {
      text += " (index: ";
      for (size_t i = 0; i < p.choices.size(); ++i)
        text += (i ? ", " : "") + std::to_string(i) + " = " + p.choices[i];
      text += ")";
    }
    text += "\n";
  }
  return text + kFixedBlock;
}

std::string glsl_abi_text() {
  return "GLSL plug-in ABI (CONTRACT §7). aoeval compiles each shader of \"shaders\" as a Vulkan\n"
         "compute shader (GLSL 450, SPIR-V 1.3, Vulkan 1.1) with the preamble below inserted "
         "after\n"
         "its #version line, then dispatches it once per frame over ceil(width / local_size_x) x\n"
         "ceil(height / local_size_y) work groups, in manifest order, with a barrier between\n"
         "passes and a GPU timestamp span around each (results column <shader stem>_ms; the frame\n"
         "time is the first to the last timestamp). The passes ping-pong two r32f images: pass k\n"
         "reads pass k-1's output as aoeval_prev and writes aoeval_out; the last pass's "
         "aoeval_out\n"
         "is the estimate's AO (values in [0, 1]; pixels with A = 0 are ignored). Parameters are\n"
         "the manifest's, in its order, as aoeval.params.<name>: real -> float, integer -> int,\n"
         "boolean -> bool, choice -> int (the index into its choices). The G-buffer is the\n"
         "shared Embree one (CONTRACT §4), uploaded once per view outside the timed frame.\n"
         "`aoeval estimators abi NAME` prints a plug-in's preamble with its parameters.\n\n"
         "Limits. A frame longer than the manifest's timeout_s is not waited for: the row is\n"
         "`skipped: ... timed out after N s` and the next frame gets a new Vulkan device (on\n"
         "lavapipe the abandoned work keeps the CPU busy until it ends or aoeval exits).\n"
         "lavapipe (Mesa's CPU device, the default) STOPS LOOPS AFTER 65,535 ITERATIONS PER\n"
         "INVOCATION, all loops of the invocation counted together (nested or one after\n"
         "another), silently: more is cut short and an endless loop \"finishes\". Keep the total\n"
         "below that (put the work in the loop body, or in more passes). aoeval warns in the\n"
         "row's derived column (\"warning\") when a shader compares with a constant above it,\n"
         "has a loop with no test of its own (while (true), for (;;)), or its integer parameters\n"
         "(other than seed) or their product exceed it; other bounds are not seen.\n\n"
         "Over time (CONTRACT §10; ABI version 2, version 1's bindings 0-7 unchanged). Over a\n"
         "sequence one instance of the plug-in runs every frame in order on one device, with that\n"
         "frame's G-buffer and camera: aoeval.frame is the frame index k (0 on a still view);\n"
         "aoeval_motion.xy is the G-buffer's motion.X/Y in pixels (the pixel's surface point was\n"
         "at its centre - xy in frame k-1); aoeval_disoccluded is 1 where that point was not\n"
         "visible in frame k-1; aoeval_history is the plug-in's own final output of frame k-1\n"
         "(the last pass's aoeval_out as written, before aoeval clamps it to [0, 1]), to be read\n"
         "at the pixel (a static camera) or at its centre - motion (reprojection, bilinear reads\n"
         "your own). All three are zero on a still view and at frame 0, and history is zero again\n"
         "after a frame past timeout_s (a new device). The seed rule: frame k runs with seed + k\n"
         "(aoeval.params.seed, aoeval.pass.z and the noise tile; seed when the run says\n"
         "\"seed_per_frame\": false), so a per-pixel noise rotation changes every frame by "
         "itself.\n\n"
         "#version 450\n" +
         glsl_abi_preamble({});
}

CompiledShader compile_glsl_compute(const std::string& file, const std::string& source,
                                    const std::vector<ParamSpec>& params) {
  const std::string preamble = glsl_abi_preamble(params);
  const std::string version = std::to_string(GLSLANG_VERSION_MAJOR) + "." +
                              std::to_string(GLSLANG_VERSION_MINOR) + "." +
                              std::to_string(GLSLANG_VERSION_PATCH);
  // The cache key: everything the SPIR-V depends on; two independent 64-bit hashes.
  const std::string keyed = "glslang " + version + " vulkan1.1 spv1.3\n" + preamble + "\n" + source;
  const std::string key = hex64(fnv1a(keyed)) + hex64(fnv1a("aoeval-salt:" + keyed));
  const fs::path cached = fs::path(data_cache_dir()) / "spirv" / (key + ".spv");
  CompiledShader out;
  std::error_code ec;
  if (fs::is_regular_file(cached, ec)) {
    std::ifstream in(cached, std::ios::binary);
    const auto bytes = static_cast<size_t>(fs::file_size(cached, ec));
    out.spirv.resize(bytes / 4);
    in.read(reinterpret_cast<char*>(out.spirv.data()), static_cast<std::streamsize>(bytes & ~3u));
    if (in && bytes % 4 == 0 && local_size_of(out.spirv, out.local_size)) {
      out.from_cache = true;
      return out;
    }
    out.spirv.clear();  // a damaged entry: compile again and replace it
  }
  {
    std::lock_guard<std::mutex> lock(glslang_mutex());
    static const bool initialised = glslang::InitializeProcess();
    if (!initialised) throw std::runtime_error("glslang::InitializeProcess failed");
    glslang::TShader shader(EShLangCompute);
    const char* strings[] = {source.c_str()};
    const int lengths[] = {static_cast<int>(source.size())};
    const char* names[] = {file.c_str()};
    shader.setStringsWithLengthsAndNames(strings, lengths, names, 1);
    shader.setPreamble(preamble.c_str());
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
    const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 450, false, messages))
      throw InputError(first_error(shader.getInfoLog(), file));
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) throw InputError(first_error(program.getInfoLog(), file));
    glslang::SpvOptions options;
    options.validate = true;
    glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), out.spirv, &options);
  }
  if (!local_size_of(out.spirv, out.local_size))
    throw InputError(file +
                     ": the work-group size must be literal (layout(local_size_x = ...) in)");
  fs::create_directories(cached.parent_path(), ec);
  std::string bytes(reinterpret_cast<const char*>(out.spirv.data()), out.spirv.size() * 4);
  try {
    write_text(cached.string(), bytes);  // atomic: temp + rename, so readers see whole entries
  } catch (const std::exception&) {
    // An unwritable cache costs a recompilation next time, nothing else.
  }
  return out;
}

std::vector<std::string> lavapipe_loop_risks(const std::vector<uint32_t>& words) {
  // SPIR-V opcodes (SPIR-V 1.3 specification, section 3.32).
  constexpr uint32_t kTypeInt = 21, kConstantTrue = 41, kConstant = 43, kLoopMerge = 246,
                     kBranchConditional = 250, kFirstIntCompare = 170, kLastIntCompare = 179;
  std::set<uint32_t> int_types, signed_types, true_ids, merges, tested_exits;
  std::map<uint32_t, int64_t> big;  // id -> value of an integer constant above the cap
  int64_t compared = 0;
  for (size_t i = 5; i < words.size();) {
    const uint32_t count = words[i] >> 16, op = words[i] & 0xffffu;
    if (count == 0 || i + count > words.size()) break;
    const uint32_t* w = &words[i];
    if (op == kTypeInt && count >= 4) {
      int_types.insert(w[1]);
      if (w[3]) signed_types.insert(w[1]);
    } else if (op == kConstantTrue && count >= 3) {
      true_ids.insert(w[2]);
    } else if (op == kConstant && count == 4 && int_types.count(w[1])) {
      const int64_t v = signed_types.count(w[1]) ? static_cast<int64_t>(static_cast<int32_t>(w[3]))
                                                 : static_cast<int64_t>(w[3]);
      if (v > kLavapipeLoopCap) big[w[2]] = v;
    } else if (op == kLoopMerge && count >= 3) {
      merges.insert(w[1]);
    } else if (op == kBranchConditional && count >= 4 && !true_ids.count(w[1])) {
      // glslang branches straight to a loop's merge block only from the loop's own test (while,
      // for, do-while); a break goes through a block of its own.
      tested_exits.insert(w[2]);
      tested_exits.insert(w[3]);
    } else if (op >= kFirstIntCompare && op <= kLastIntCompare && count >= 5) {
      for (uint32_t operand : {w[3], w[4]})
        if (big.count(operand)) compared = std::max(compared, big[operand]);
    }
    i += count;
  }
  std::vector<std::string> risks;
  if (merges.empty()) return risks;
  if (compared > 0) risks.push_back("a loop bound of " + std::to_string(compared));
  for (uint32_t m : merges) {
    if (tested_exits.count(m)) continue;
    risks.push_back("an endless loop (left by a break, if at all)");
    break;
  }
  return risks;
}

std::vector<PassShader> compile_glsl_plugin(const PluginManifest& m) {
  std::vector<PassShader> shaders;
  const std::vector<std::string> passes = plugin_pass_names(m);
  for (size_t i = 0; i < m.shaders.size(); ++i) {
    const std::string path = (fs::path(m.folder) / m.shaders[i]).string();
    shaders.push_back({passes[i], compile_glsl_compute(path, read_text_file(path), m.params)});
  }
  return shaders;
}

namespace {

// GLSL plug-ins run on a Vulkan context of their own, not the shared one: a shader that overruns
// its timeout_s cannot be stopped (Vulkan has no way to cancel a dispatch, and lavapipe runs it on
// CPU threads to its end), so its context is abandoned with everything made from it, never
// destroyed (destroying a busy device is invalid), and the next frame gets a fresh context, while
// the built-in estimators' shared context is untouched. Abandoned contexts stay reachable here.
struct PluginContexts {
  std::mutex mutex;
  std::unique_ptr<vk::Context> current;
  std::vector<std::unique_ptr<vk::Context>>* abandoned =
      new std::vector<std::unique_ptr<vk::Context>>;
};
PluginContexts& plugin_contexts() {
  static PluginContexts contexts;
  return contexts;
}

vk::Context& plugin_context() {
  PluginContexts& c = plugin_contexts();
  std::lock_guard lock(c.mutex);
  if (!c.current) {
    std::string reason;
    c.current = vk::Context::create({}, &reason);
    if (!c.current) throw EstimatorUnavailable("no Vulkan device (" + reason + ")");
  }
  return *c.current;
}

void abandon_plugin_context(const vk::Context* context) {
  PluginContexts& c = plugin_contexts();
  std::lock_guard lock(c.mutex);
  if (c.current.get() == context) c.abandoned->push_back(std::move(c.current));
}

struct Mat4 {
  float m[16] = {};  // column-major, as GLSL reads a mat4 in std140
  float& at(int row, int col) { return m[col * 4 + row]; }
};

class GlslEstimator : public Estimator {
 public:
  GlslEstimator(const PluginManifest& m, const ParamSet& params)
      : manifest_(m), params_(params), shaders_(compile_glsl_plugin(m)) {
    for (const PassShader& s : shaders_)
      for (const std::string& risk : lavapipe_loop_risks(s.code.spirv))
        loop_risks_.push_back(s.name + ": " + risk);
    // Integer parameters are the usual loop bounds (samples, steps, taps): their product is what
    // nested loops run ("seed" is a number, never a bound).
    std::string names;
    int64_t product = 1;
    for (const ParamSpec& p : m.params) {
      if (p.type != ParamType::integer || p.name == "seed") continue;
      const int64_t v = params.json().at(p.name).get<int64_t>();
      if (v <= 1) continue;
      names += (names.empty() ? "" : " x ") + p.name;
      product = std::min(product * std::min(v, kLavapipeLoopCap + 1), int64_t{1} << 40);
      if (v > kLavapipeLoopCap)
        loop_risks_.push_back("parameter " + p.name + " = " + std::to_string(v));
    }
    if (loop_risks_.empty() && product > kLavapipeLoopCap && names.find(" x ") != std::string::npos)
      loop_risks_.push_back("parameters " + names + " = " + std::to_string(product));
  }

  // The row's warning when lavapipe's loop cap may have cut this estimate short (see
  // lavapipe_loop_risks); other devices have no such cap.
  nlohmann::json derived() const override {
    nlohmann::json d = nlohmann::json::object();
    if (on_lavapipe_ && !loop_risks_.empty()) {
      std::string list;
      for (const std::string& r : loop_risks_) list += (list.empty() ? "" : "; ") + r;
      d["warning"] = "lavapipe ends loops after " + std::to_string(kLavapipeLoopCap) +
                     " iterations per invocation (all loops together), and this shader may need "
                     "more (" +
                     list + ")";
    }
    return d;
  }

  // Over a sequence one instance runs every frame in order (EstimatorInfo::keeps_state): the
  // device, its pipelines and the last frame's output stay, and each frame uploads its own
  // G-buffer, motion, noise (the seed rule: seed + k) and uniform block.
  void prepare(const EstimateContext& context) override {
    const GBuffer& g = context.gbuffer;
    frame_ = context.frame ? *context.frame : FrameInfo{};  // a still view is frame 0
    still_ = context.frame == nullptr;
    if (!device_ || device_->depth.width() != g.width || device_->depth.height() != g.height)
      make_device(g.width, g.height);
    Device& d = *device_;
    d.upload(g);
    // The noise tile: kNoiseSize^2 texels of four uniform numbers in [0, 1), from the seed.
    SplitMix64 random(mix_seed(static_cast<uint64_t>(seed()), 0x4E4F4953));  // "NOIS"
    std::vector<float> noise(4 * kNoiseSize * kNoiseSize);
    for (float& v : noise) v = random.uniform_float();
    d.noise.upload(noise);
    for (size_t i = 0; i < shaders_.size(); ++i) {
      // One block per pass: they differ only in aoeval.pass.x.
      const std::vector<uint8_t> block = uniform_block(g, static_cast<int32_t>(i));
      d.uniforms[i].upload(block.data(), block.size());
    }
    prepared_for_ = &g;
  }

  EstimateResult run(const EstimateContext& context) override {
    const int index = context.frame ? context.frame->index : 0;
    const uint64_t offset = context.frame ? context.frame->seed_offset : 0;
    if (prepared_for_ != &context.gbuffer || !device_ || still_ != (context.frame == nullptr) ||
        frame_.index != index || frame_.seed_offset != offset)
      prepare(context);
    Device& d = *device_;
    const GBuffer& g = context.gbuffer;
    // aoeval_history: frame k - 1's final output, still in its ping image; zero on a still view,
    // at frame 0, and when frame k - 1 did not run on this device (a time-out gave a new one).
    // A second run of frame k keeps its history (frame k - 1's), so repeated runs agree.
    const History history = still_ || index == 0       ? History::clear
                            : last_frame_ == index - 1 ? History::copy
                            : last_frame_ == index     ? History::keep
                                                       : History::clear;
    const size_t last = (shaders_.size() - 1) % 2;
    // What the recording needs, by value: after a time-out the recording thread outlives this
    // call (and maybe the estimator); only `d`, then abandoned and never freed, is shared.
    struct Pass {
      std::string name;
      uint32_t groups_x, groups_y;
    };
    std::vector<Pass> passes;
    for (const PassShader& s : shaders_)
      passes.push_back({s.name,
                        vk::group_count(static_cast<uint32_t>(g.width), s.code.local_size[0]),
                        vk::group_count(static_cast<uint32_t>(g.height), s.code.local_size[1])});
    const bool bent = manifest_.bent;
    auto record = [&d, passes, bent, history, last](VkCommandBuffer cmd) {
      d.timer.reset(cmd);
      const VkClearColorValue zero{};
      VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      if (history == History::copy) {
        VkImageCopy copy{};
        copy.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.dstSubresource = copy.srcSubresource;
        copy.extent = {static_cast<uint32_t>(d.history.width()),
                       static_cast<uint32_t>(d.history.height()), 1};
        vkCmdCopyImage(cmd, d.ping[last].handle(), VK_IMAGE_LAYOUT_GENERAL, d.history.handle(),
                       VK_IMAGE_LAYOUT_GENERAL, 1, &copy);
        vk::pass_barrier(cmd);
      } else if (history == History::clear) {
        vkCmdClearColorImage(cmd, d.history.handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
      }
      // A frame's passes start from zeros, whatever the last frame left.
      for (const vk::Image2D* image : {&d.ping[0], &d.ping[1], &d.bent})
        if (image != &d.bent || bent)
          vkCmdClearColorImage(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
      vk::pass_barrier(cmd);
      for (size_t i = 0; i < passes.size(); ++i) {
        d.timer.begin(cmd, passes[i].name);
        d.pipelines[i]->dispatch(cmd, d.sets[i], static_cast<const void*>(nullptr), size_t{0},
                                 passes[i].groups_x, passes[i].groups_y);
        d.timer.end(cmd);
        vk::pass_barrier(cmd);
      }
    };
    submit_within_timeout(record);
    last_frame_ = still_ ? -1 : index;
    EstimateResult r;
    r.pass_ms = d.timer.read();
    if (!r.pass_ms.empty()) r.timing_source = "gpu-timestamps";
    r.ao = d.ping[last].download<float>();
    for (size_t k = 0; k < r.ao.size(); ++k) {
      if (!g.covered(k)) {
        r.ao[k] = 0.0f;
        continue;
      }
      // The same checks and range rule as a process plug-in's output (plugin_process.h).
      const float v = r.ao[k];
      if (!std::isfinite(v) || v < -kAoRangeSlack || v > 1.0f + kAoRangeSlack) {
        char where[64];
        std::snprintf(where, sizeof(where), " at covered pixel (%zu, %zu)",
                      k % static_cast<size_t>(g.width), k / static_cast<size_t>(g.width));
        throw EstimatorUnavailable("plug-in " + manifest_.name + ": AO " +
                                   (std::isfinite(v) ? "= " + format_param_value(v) +
                                                           std::string(where) + " is outside [0, 1]"
                                                     : "is not finite" + std::string(where)));
      }
      r.ao[k] = std::clamp(v, 0.0f, 1.0f);
    }
    if (manifest_.bent) {
      const std::vector<float> b = d.bent.download<float>();
      const Camera& c = g.camera;
      for (const char* axis : {"bent.X", "bent.Y", "bent.Z"})
        r.extra_channels[axis].assign(g.pixel_count(), 0.0f);
      for (size_t k = 0; k < g.pixel_count(); ++k) {
        if (!g.covered(k)) continue;
        // eye -> world: x along right, y along up, z against forward.
        const glm::vec3 w = b[4 * k] * c.right + b[4 * k + 1] * c.up - b[4 * k + 2] * c.forward;
        r.extra_channels["bent.X"][k] = w.x;
        r.extra_channels["bent.Y"][k] = w.y;
        r.extra_channels["bent.Z"][k] = w.z;
      }
    }
    return r;
  }

 private:
  struct Device {
    vk::Context& vk;
    vk::Image2D depth, normal, position, ping[2], bent, noise, motion, disoccluded, history;
    std::vector<vk::Buffer> uniforms;  // one per pass
    vk::PassTimer timer;
    std::vector<std::unique_ptr<vk::ComputePipeline>> pipelines;
    std::vector<VkDescriptorSet> sets;

    Device(vk::Context& context, int w, int h, uint32_t passes)
        : vk(context), timer(context, passes) {
      depth = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
      normal = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      position = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      for (auto& p : ping) p = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
      bent = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      noise = vk::Image2D(vk, kNoiseSize, kNoiseSize, VK_FORMAT_R32G32B32A32_SFLOAT);
      motion = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      disoccluded = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
      history = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
    }

    // The frame's G-buffer in eye space, its motion and disocclusion (zeros on a still view).
    void upload(const GBuffer& g) {
      const Camera& c = g.camera;
      const size_t count = g.pixel_count();
      const bool moving = g.motion.size() == count && g.disoccluded.size() == count;
      std::vector<float> z(count), n(4 * count), p(4 * count), m(4 * count, 0.0f), dis(count, 0.0f);
      for (size_t k = 0; k < count; ++k) {
        const bool covered = g.covered(k);
        z[k] = covered ? g.depth[k] : 0.0f;
        const glm::vec3 d = g.position[k] - c.eye;
        const glm::vec3 pe(glm::dot(d, c.right), glm::dot(d, c.up), -glm::dot(d, c.forward));
        const glm::vec3 ne(glm::dot(g.normal[k], c.right), glm::dot(g.normal[k], c.up),
                           -glm::dot(g.normal[k], c.forward));
        for (int a = 0; a < 3; ++a) {
          n[4 * k + a] = covered ? ne[a] : 0.0f;
          p[4 * k + a] = covered ? pe[a] : 0.0f;
        }
        n[4 * k + 3] = covered ? 1.0f : 0.0f;
        p[4 * k + 3] = covered ? g.object_id[k] : -1.0f;
        if (moving && covered) {
          m[4 * k] = g.motion[k].x;
          m[4 * k + 1] = g.motion[k].y;
          dis[k] = g.disoccluded[k];
        }
      }
      depth.upload(z);
      normal.upload(n);
      position.upload(p);
      motion.upload(m);
      disoccluded.upload(dis);
    }
  };

  enum class History { clear, copy, keep };

  // A device of this size with the passes' pipelines and descriptor sets; frame k - 1's output is
  // not on it, so the next frame's history is zero.
  void make_device(int w, int h) {
    vk::Context& vk = plugin_context();
    on_lavapipe_ = vk.device_name().find("llvmpipe") != std::string::npos;
    device_ = std::make_unique<Device>(vk, w, h, static_cast<uint32_t>(shaders_.size()));
    Device& d = *device_;
    last_frame_ = -1;
    const size_t block_bytes = uniform_block_bytes();
    for (size_t i = 0; i < shaders_.size(); ++i) {
      d.uniforms.emplace_back(vk, block_bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
      vk::SpirvCode code;
      code.words = shaders_[i].code.spirv.data();
      code.bytes = shaders_[i].code.spirv.size() * sizeof(uint32_t);
      auto pipeline = std::make_unique<vk::ComputePipeline>(
          vk, manifest_.name + " " + shaders_[i].name, code, kBindings);
      // Ping-pong: pass k writes ping[k % 2] and reads the other.
      const vk::Image2D& out = d.ping[i % 2];
      const vk::Image2D& prev = d.ping[(i + 1) % 2];
      d.sets.push_back(
          pipeline->make_set({d.depth, d.normal, d.position, prev, out, d.bent, d.noise,
                              d.uniforms[i], d.motion, d.disoccluded, d.history}));
      d.pipelines.push_back(std::move(pipeline));
    }
  }

  // Submits the frame and waits for it at most the manifest's timeout_s. The wait runs on a
  // thread of its own because a driver may execute the work inside vkQueueSubmit (lavapipe may)
  // or never signal the fence; on a time-out that thread, the device objects and the context are
  // abandoned (see plugin_context()), and the frame is an EstimatorUnavailable: a skipped row.
  void submit_within_timeout(const std::function<void(VkCommandBuffer)>& record) {
    Device& d = *device_;
    auto done = std::make_shared<std::promise<void>>();
    std::future<void> finished = done->get_future();
    std::thread worker([&vk = d.vk, record, done] {
      try {
        vk.submit(record);
        done->set_value();
      } catch (...) {
        done->set_exception(std::current_exception());
      }
    });
    const auto limit = std::chrono::duration<double>(manifest_.timeout_s);
    if (finished.wait_for(limit) == std::future_status::timeout) {
      worker.detach();
      abandon_plugin_context(&d.vk);
      (void)device_.release();  // its objects belong to the abandoned device: never destroyed
      prepared_for_ = nullptr;
      throw EstimatorUnavailable("plug-in " + manifest_.name + " timed out after " +
                                 format_param_value(manifest_.timeout_s) +
                                 " s (its Vulkan device was abandoned; the next frame gets a new "
                                 "one)");
    }
    worker.join();
    finished.get();  // a VulkanError of the submit, rethrown here
  }

  // The std140 bytes of the aoeval block: 4 mat4, 3 vec4, 1 ivec4, the int frame (padded to 16:
  // a struct member starts on a 16-byte boundary), then one 4-byte scalar per parameter in
  // manifest order (a struct of scalars: 4-byte alignment, 16-byte size rounding).
  // The noise seed: the parameter "seed" when the plug-in declares an integer one, plus the
  // frame's seed offset (the seed rule, CONTRACT §10: k, or 0 under "seed_per_frame": false),
  // wrapped to 32 bits; else 0. aoeval.params.seed holds the same value.
  int32_t seed() const {
    const nlohmann::json values = frame_param_values(manifest_, params_.json(), &frame_);
    if (!values.contains("seed") || !values["seed"].is_number_integer()) return 0;
    return static_cast<int32_t>(static_cast<uint32_t>(values["seed"].get<int64_t>()));
  }

  size_t uniform_block_bytes() const {
    const size_t scalars = std::max<size_t>(manifest_.params.size(), 1);
    return (4 * 64 + 4 * 16 + 16 + 4 * scalars + 15) / 16 * 16;
  }

  std::vector<uint8_t> uniform_block(const GBuffer& g, int32_t pass_index) const {
    const Camera& c = g.camera;
    const auto w = static_cast<float>(g.width), h = static_cast<float>(g.height);
    const float f = h / (2.0f * c.tan_half_fov_y), aspect = w / h;
    Mat4 proj, inv_proj, view, inv_view;
    proj.at(0, 0) = 2.0f * f / w;
    proj.at(1, 1) = -2.0f * f / h;
    proj.at(2, 3) = kNearPlane;  // z_clip = near, w_clip = -z_eye: depth near / -z_eye
    proj.at(3, 2) = -1.0f;
    inv_proj.at(0, 0) = w / (2.0f * f);
    inv_proj.at(1, 1) = -h / (2.0f * f);
    inv_proj.at(2, 3) = -1.0f;
    inv_proj.at(3, 2) = 1.0f / kNearPlane;
    const glm::vec3 axes[3] = {c.right, c.up, -c.forward};
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) {
        view.at(r, k) = axes[r][k];
        inv_view.at(k, r) = axes[r][k];
      }
      view.at(r, 3) = -glm::dot(axes[r], c.eye);
      inv_view.at(r, 3) = c.eye[r];
    }
    view.at(3, 3) = inv_view.at(3, 3) = 1.0f;
    std::vector<uint8_t> bytes;
    auto put = [&](const void* data, size_t n) {
      const auto* b = static_cast<const uint8_t*>(data);
      bytes.insert(bytes.end(), b, b + n);
    };
    for (const Mat4* m : {&proj, &inv_proj, &view, &inv_view}) put(m->m, sizeof(m->m));
    const float eye[4] = {c.eye.x, c.eye.y, c.eye.z, 1.0f};
    const float size[4] = {w, h, 1.0f / w, 1.0f / h};
    const float lens[4] = {f, c.tan_half_fov_y * aspect, c.tan_half_fov_y, aspect};
    const nlohmann::json& values = params_.json();
    const int32_t pass[4] = {pass_index, static_cast<int32_t>(shaders_.size()), seed(), kNoiseSize};
    put(eye, 16);
    put(size, 16);
    put(lens, 16);
    put(pass, 16);
    const int32_t frame[4] = {frame_.index, 0, 0, 0};
    put(frame, 16);
    for (const auto& p : manifest_.params) {
      const nlohmann::json& v = values.at(p.name);
      uint32_t bits = 0;
      if (p.name == "seed" && p.type == ParamType::integer) {
        const int32_t x = seed();
        std::memcpy(&bits, &x, 4);
      } else if (p.type == ParamType::real) {
        const auto x = static_cast<float>(v.get<double>());
        std::memcpy(&bits, &x, 4);
      } else if (p.type == ParamType::integer) {
        const auto x = static_cast<int32_t>(v.get<int64_t>());
        std::memcpy(&bits, &x, 4);
      } else if (p.type == ParamType::boolean) {
        bits = v.get<bool>() ? 1u : 0u;
      } else {
        for (size_t i = 0; i < p.choices.size(); ++i)
          if (p.choices[i] == v.get<std::string>()) bits = static_cast<uint32_t>(i);
      }
      put(&bits, 4);
    }
    if (manifest_.params.empty()) bytes.resize(bytes.size() + 4, 0);
    bytes.resize(uniform_block_bytes(), 0);
    return bytes;
  }

  PluginManifest manifest_;
  ParamSet params_;
  std::vector<PassShader> shaders_;
  std::unique_ptr<Device> device_;
  const GBuffer* prepared_for_ = nullptr;
  FrameInfo frame_;      // the frame prepared for (index 0, no seed offset on a still view)
  bool still_ = true;    // prepared for a still view (EstimateContext::frame null)
  int last_frame_ = -1;  // the frame whose output the device's last ping image holds; -1 none
  std::vector<std::string> loop_risks_;
  bool on_lavapipe_ = false;
};

}  // namespace

std::unique_ptr<Estimator> make_glsl_estimator(const PluginManifest& m, const ParamSet& params) {
  return std::make_unique<GlslEstimator>(m, params);
}

}  // namespace aoeval
