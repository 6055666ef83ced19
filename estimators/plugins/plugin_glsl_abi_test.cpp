// The GLSL ABI check (check_glsl_abi): a shader's SPIR-V is reflected before any pipeline is built,
// and a descriptor that is not the preamble's own, or a push-constant block, is an InputError
// naming the shader file, the line and the binding. The shaders below crashed lavapipe (a
// sampler2D at binding 10: SIGBUS; a descriptor in set 1: SIGSEGV) or ran on undefined data (a
// storage image past the last binding, an SSBO written at binding 9, a push-constant block) before the
// check. No Vulkan device is needed: the check runs on the compiled words.
#include <gtest/gtest.h>

#include <filesystem>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "estimators/plugins/plugin_glsl.h"
#include "estimators/plugins/plugin_glsl_abi.h"
#include "estimators/plugins/plugin_manifest.h"
#include "estimators/plugins/plugin_registry.h"
#include "estimators/plugins/spirv_reflect.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

void use_private_cache() {
  setenv("AOEVAL_CACHE", (testutil::test_temp_dir("glsl_abi") / "cache").c_str(), 1);
}

// A shader whose declarations are `decls` (from line 3 on) and whose main() writes aoeval_out.
std::string shader(const std::string& decls, const std::string& body = "") {
  return "#version 450\nlayout(local_size_x = 8, local_size_y = 8) in;\n" + decls +
         "void main() {\n  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n" + body +
         "  imageStore(aoeval_out, p, vec4(1.0));\n}\n";
}

// The InputError compiling `source` as `file` throws ("" when it compiles and passes the check).
std::string refusal(const std::string& file, const std::string& source) {
  try {
    compile_glsl_compute(file, source, {});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(GlslAbiCheck, ThePreambleReflectsToTheBindingTable) {
  use_private_cache();
  const CompiledShader c = compile_glsl_compute("empty.comp", shader(""), {});
  const SpirvReflection r = reflect_spirv(c.spirv);
  EXPECT_TRUE(r.push_constants.empty());
  ASSERT_EQ(r.descriptors.size(), kGlslBindings.size());
  ASSERT_EQ(kGlslBindingNames.size(), kGlslBindings.size());
  for (const SpirvDescriptor& d : r.descriptors) {
    SCOPED_TRACE(d.name);
    EXPECT_EQ(d.set, 0u);
    ASSERT_LT(d.binding, kGlslBindings.size());
    EXPECT_EQ(d.name, kGlslBindingNames[d.binding]);
    EXPECT_EQ(d.kind, kGlslBindings[d.binding] == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER
                          ? SpirvDescriptorKind::uniform_buffer
                          : SpirvDescriptorKind::storage_image);
    EXPECT_EQ(d.array_size, 1u);
  }
}

struct BadShader {
  const char* case_name;
  const char* decls;
  const char* body;
  const char* expected;  // in the message, after "<file>:3: "
};

class GlslAbiRefuses : public testing::TestWithParam<BadShader> {};

TEST_P(GlslAbiRefuses, NamingTheFileLineAndBinding) {
  use_private_cache();
  const BadShader& b = GetParam();
  const std::string file = std::string(b.case_name) + ".comp";
  const std::string what = refusal(file, shader(b.decls, b.body));
  ASSERT_FALSE(what.empty()) << b.case_name << " passed the check";
  EXPECT_EQ(what.rfind(file + ":3: ", 0), 0u) << what;
  EXPECT_NE(what.find(b.expected), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

INSTANTIATE_TEST_SUITE_P(
    Shaders, GlslAbiRefuses,
    testing::Values(
        BadShader{"sampler_at_10", "layout(set = 0, binding = 10) uniform sampler2D tex;\n",
                  "  float t = texture(tex, vec2(0.5)).x;\n",
                  "`tex`, a combined image sampler (sampler2D) at set 0, binding 10: that "
                  "binding is aoeval's aoeval_history, a storage image"},
        BadShader{"set_1", "layout(set = 1, binding = 0, r32f) uniform readonly image2D extra;\n",
                  "  float t = imageLoad(extra, p).x;\n",
                  "`extra`, a storage image (image2D) at set 1, binding 0: aoeval's GLSL ABI "
                  "binds descriptor set 0 only"},
        BadShader{"image_at_12",
                  "layout(set = 0, binding = 12, r32f) uniform writeonly image2D scratch;\n",
                  "  imageStore(scratch, p, vec4(0.0));\n",
                  "at set 0, binding 12: aoeval's GLSL ABI has bindings 0..11 only"},
        BadShader{"r32f_image_at_11",
                  "layout(set = 0, binding = 11, r32f) uniform writeonly image2D scratch;\n",
                  "  imageStore(scratch, p, vec4(0.0));\n",
                  "at set 0, binding 11: that binding is aoeval's aoeval_state"},
        BadShader{"ssbo_at_9",
                  "layout(std430, set = 0, binding = 9) buffer Scratch { float v[]; } scratch;\n",
                  "  scratch.v[p.x] = 1.0;\n",
                  "`scratch`, a buffer block (SSBO) at set 0, binding 9: that binding is "
                  "aoeval's aoeval_disoccluded"},
        BadShader{"push_constants", "layout(push_constant) uniform Push { float gain; } push;\n",
                  "  float g = push.gain;\n", "push-constant block `push`"},
        BadShader{"alias_of_another_format",
                  "layout(set = 0, binding = 3, rgba32f) uniform readonly image2D prev4;\n",
                  "  vec4 q = imageLoad(prev4, p);\n",
                  "`prev4`, a storage image (image2D) at set 0, binding 3: that binding is "
                  "aoeval's aoeval_prev"},
        BadShader{"unused_uniform_block",
                  "layout(std140, set = 0, binding = 7) uniform Mine { vec4 x; } mine;\n", "",
                  "binding 7: that binding is aoeval's aoeval, a uniform block"}),
    [](const testing::TestParamInfo<BadShader>& param_info) {
      return std::string(param_info.param.case_name);
    });

// A shader taken from the SPIR-V cache is checked like a new one: the cache holds no refused
// shader, and a compiled one checks again on the way out of the cache.
TEST(GlslAbiCheck, ARefusedShaderIsRefusedAgainAndNotCached) {
  use_private_cache();
  const std::string source = shader("layout(set = 1, binding = 2) uniform sampler2D s;\n");
  const std::string first = refusal("again.comp", source), second = refusal("again.comp", source);
  EXPECT_FALSE(first.empty());
  EXPECT_EQ(first, second);
}

TEST(GlslAbiCheck, TheShippedGlslExamplesPass) {
  use_private_cache();
  for (const char* name : {"alchemy", "sao", "history-ssao"}) {
    SCOPED_TRACE(name);
    const PluginManifest m =
        read_plugin_manifest((fs::path(shipped_plugins_dir()) / name).string());
    // Twice: compiled, then from the cache; both go through the check.
    for (int pass = 0; pass < 2; ++pass)
      for (const PassShader& s : compile_glsl_plugin(m)) {
        if (pass == 1) {
          EXPECT_TRUE(s.code.from_cache);
        }
        const SpirvReflection r = reflect_spirv(s.code.spirv);
        EXPECT_TRUE(r.push_constants.empty());
        for (const SpirvDescriptor& d : r.descriptors) EXPECT_EQ(d.set, 0u) << d.name;
      }
  }
}

TEST(GlslAbiCheck, UsingTheAbiPasses) {
  use_private_cache();
  EXPECT_EQ(refusal("fine.comp", shader("shared float tile[64];\n",
                                        "  float h = imageLoad(aoeval_history, p).x;\n"
                                        "  vec4 m = imageLoad(aoeval_motion, p);\n")),
            "");
}

TEST(SpirvReflect, RefusesWordsThatAreNotSpirv) {
  EXPECT_THROW(reflect_spirv({1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(reflect_spirv({0x07230203, 0x00010300, 0, 20, 0, (9u << 16) | 5u}),
               std::invalid_argument);
}

}  // namespace
}  // namespace aoeval
