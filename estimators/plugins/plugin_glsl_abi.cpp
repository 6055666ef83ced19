// GLSL plug-ins, the ABI (CONTRACT §7): the preamble aoeval compiles into every shader, its text
// as `aoeval estimators abi` prints it, the binding table and the bytes of the uniform block.
#include "estimators/plugins/plugin_glsl_abi.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>

#include "base/errors.h"
#include "estimators/plugins/plugin_glsl.h"
#include "estimators/plugins/spirv_reflect.h"

namespace aoeval {

// The binding table of the ABI; the preamble below declares the same, in this order.
const std::vector<VkDescriptorType> kGlslBindings = {
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
    // Version 3: the plug-in's own state between frames (CONTRACT §10's history, widened).
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,  // 11 aoeval_state
};
const std::vector<std::string> kGlslBindingNames = {
    "aoeval_depth",  "aoeval_normal",      "aoeval_position", "aoeval_prev",
    "aoeval_out",    "aoeval_bent",        "aoeval_noise",    "aoeval",
    "aoeval_motion", "aoeval_disoccluded", "aoeval_history",  "aoeval_state"};

namespace {

constexpr float kNearPlane = 0.01f;  // of the reversed-Z projection, scene units

const char* kFixedPreamble =
    R"(// ---- aoeval GLSL plug-in ABI, version 3 (aoeval estimators abi) ----
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
// Version 3. Four floats per pixel that are the plug-in's own (a history length, moments, an
// object id): aoeval never reads, checks or clamps them; every pass may read and write them, and
// each frame starts with what the previous frame's last pass left (zeros at frame 0, on a still
// view and after a frame that did not run; a repeated frame starts from the same values again).
layout(set = 0, binding = 11, rgba32f) uniform image2D aoeval_state;
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

struct Mat4 {
  float m[16] = {};  // column-major, as GLSL reads a mat4 in std140
  float& at(int row, int col) { return m[col * 4 + row]; }
};

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
         "Checked before any pipeline is built: aoeval reflects each compiled shader's SPIR-V\n"
         "and refuses (exit 2, naming the shader, the line and the binding) any descriptor that\n"
         "is not one of the preamble's: a set other than 0, a binding above 11, another type or\n"
         "a second variable at one of its bindings (a sampler2D, a buffer block, an image of\n"
         "another format), and any push-constant block. The shader's own data belongs in\n"
         "aoeval.params, its scratch in shared memory or more passes.\n\n"
         "Over time (CONTRACT §10; ABI version 2, version 1's bindings 0-7 unchanged). Over a\n"
         "sequence one instance of the plug-in runs every frame in order on one device, with that\n"
         "frame's G-buffer and camera: aoeval.frame is the frame index k (0 on a still view);\n"
         "aoeval_motion.xy is the G-buffer's motion.X/Y in pixels (the pixel's surface point was\n"
         "at its centre - xy in frame k-1); aoeval_disoccluded is 1 where that point was not\n"
         "visible in frame k-1; aoeval_history is the plug-in's own final output of frame k-1\n"
         "(the last pass's aoeval_out as written), to be read at the pixel (a static camera) or\n"
         "at its centre - motion (reprojection, bilinear reads your own). That output is the AO:\n"
         "on covered pixels it must be in [0, 1] (a value outside skips the row), so it cannot\n"
         "carry anything else. All three are zero on a still view and at frame 0, and history is\n"
         "zero again after a frame past timeout_s (a new device). The seed rule: frame k runs\n"
         "with seed + k\n"
         "(aoeval.params.seed, aoeval.pass.z and the noise tile; seed when the run says\n"
         "\"seed_per_frame\": false), so a per-pixel noise rotation changes every frame by "
         "itself.\n\n"
         "The plug-in's own state (ABI version 3): aoeval_state, four floats per pixel (rgba32f)\n"
         "that aoeval keeps between frames and never reads, range-checks or clamps: a history\n"
         "length, moments, an object id, whatever the plug-in needs beside its AO (the range\n"
         "check applies to the AO output only). Every pass may read and write it; frame k starts\n"
         "with what frame k-1's last pass left in it; zeros at frame 0, on a still view and after\n"
         "a frame that did not run on this device; a repeated frame k (timed repetitions) starts\n"
         "from frame k-1's values again, so repetitions agree. It is not reprojected: read it at\n"
         "centre - motion yourself, as aoeval_history.\n\n"
         "#version 450\n" +
         glsl_abi_preamble({});
}

namespace {

SpirvDescriptorKind kind_of(VkDescriptorType t) {
  switch (t) {
    case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
      return SpirvDescriptorKind::storage_image;
    case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
      return SpirvDescriptorKind::uniform_buffer;
    default:
      return SpirvDescriptorKind::other;
  }
}

bool identifier_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// The first line of `source` (1-based) naming `name` as a whole word outside a // comment: GLSL
// declares a global before any use, so that is its declaration. 0 when not found.
int declaration_line(const std::string& source, const std::string& name) {
  if (name.empty()) return 0;
  int line = 1;
  size_t start = 0;
  while (start <= source.size()) {
    size_t end = source.find('\n', start);
    if (end == std::string::npos) end = source.size();
    std::string text = source.substr(start, end - start);
    text = text.substr(0, text.find("//"));
    for (size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
      const size_t after = at + name.size();
      if ((at == 0 || !identifier_char(text[at - 1])) &&
          (after >= text.size() || !identifier_char(text[after])))
        return line;
    }
    start = end + 1;
    ++line;
  }
  return 0;
}

}  // namespace

void check_glsl_abi(const std::vector<uint32_t>& spirv, const std::string& file,
                    const std::string& source) {
  SpirvReflection r;
  try {
    r = reflect_spirv(spirv);
  } catch (const std::invalid_argument& e) {
    throw InputError(file + ": its compiled SPIR-V cannot be read (" + e.what() + ")");
  }
  const std::string see = " (see `aoeval estimators abi`)";
  auto where = [&](const std::string& name) {
    // Appended, not "+"-chained: GCC 12 warns falsely (-Wrestrict, PR 105329) on "x" + string.
    std::string text = file;
    if (const int line = declaration_line(source, name); line > 0)
      text.append(":").append(std::to_string(line));
    return text.append(": ");
  };
  if (!r.push_constants.empty()) {
    const std::string& name = r.push_constants.front();
    throw InputError(where(name) + "push-constant block `" + name +
                     "`: aoeval's GLSL ABI has no push constants (parameters come in "
                     "aoeval.params)" +
                     see);
  }
  for (const SpirvDescriptor& d : r.descriptors) {
    const std::string what = "`" + d.name + "`, " + spirv_kind_text(d.kind);
    if (!d.has_set || !d.has_binding)
      throw InputError(where(d.name) + what + " has no layout(set = 0, binding = N)" + see);
    const std::string at =
        "at set " + std::to_string(d.set) + ", binding " + std::to_string(d.binding) + ": ";
    if (d.set != 0)
      throw InputError(where(d.name) + what + " " + at +
                       "aoeval's GLSL ABI binds descriptor set 0 only" + see);
    if (d.binding >= kGlslBindings.size())
      throw InputError(where(d.name) + what + " " + at + "aoeval's GLSL ABI has bindings 0.." +
                       std::to_string(kGlslBindings.size() - 1) + " only" + see);
    const std::string& owner = kGlslBindingNames[d.binding];
    const SpirvDescriptorKind expected = kind_of(kGlslBindings[d.binding]);
    if (d.name != owner || d.kind != expected || d.array_size != 1)
      throw InputError(where(d.name) + what + (d.array_size != 1 ? " array" : "") + " " + at +
                       "that binding is aoeval's " + owner + ", " + spirv_kind_text(expected) +
                       "; declare no other variable there" + see);
  }
}

size_t glsl_uniform_block_bytes(const PluginManifest& m) {
  const size_t scalars = std::max<size_t>(m.params.size(), 1);
  return (4 * 64 + 4 * 16 + 16 + 4 * scalars + 15) / 16 * 16;
}

// The std140 bytes of the aoeval block: 4 mat4, 3 vec4, 1 ivec4, the int frame (padded to 16:
// a struct member starts on a 16-byte boundary), then one 4-byte scalar per parameter in
// manifest order (a struct of scalars: 4-byte alignment, 16-byte size rounding).
std::vector<uint8_t> glsl_uniform_block(const PluginManifest& m, const ParamSet& params,
                                        const FrameInfo& frame_info, int32_t seed, const GBuffer& g,
                                        int32_t pass_index, int32_t passes) {
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
  for (const Mat4* x : {&proj, &inv_proj, &view, &inv_view}) put(x->m, sizeof(x->m));
  const float eye[4] = {c.eye.x, c.eye.y, c.eye.z, 1.0f};
  const float size[4] = {w, h, 1.0f / w, 1.0f / h};
  const float lens[4] = {f, c.tan_half_fov_y * aspect, c.tan_half_fov_y, aspect};
  const nlohmann::json& values = params.json();
  const int32_t pass[4] = {pass_index, passes, seed, kGlslNoiseSize};
  put(eye, 16);
  put(size, 16);
  put(lens, 16);
  put(pass, 16);
  const int32_t frame[4] = {frame_info.index, 0, 0, 0};
  put(frame, 16);
  for (const auto& p : m.params) {
    const nlohmann::json& v = values.at(p.name);
    uint32_t bits = 0;
    if (p.name == "seed" && p.type == ParamType::integer) {
      const int32_t x = seed;
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
  if (m.params.empty()) bytes.resize(bytes.size() + 4, 0);
  bytes.resize(glsl_uniform_block_bytes(m), 0);
  return bytes;
}

}  // namespace aoeval
