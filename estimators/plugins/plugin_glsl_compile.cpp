// GLSL plug-ins, compiled: a shader and the ABI preamble (plugin_glsl_abi.cpp) through the
// glslang library to SPIR-V, cached by content on disk, its work-group size read back, and what
// in it lavapipe's loop cap may cut short.
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <glslang/build_info.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "base/errors.h"
#include "base/hash.h"
#include "estimators/plugins/plugin_glsl.h"
#include "estimators/plugins/plugin_glsl_abi.h"
#include "estimators/plugins/plugin_process.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

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
      check_glsl_abi(out.spirv, file, source);
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
  check_glsl_abi(out.spirv, file, source);
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

}  // namespace aoeval
