// The command line as users and scripts see it (CONTRACT §2): exit codes, one-line errors that name
// the file and the field, no partial outputs, and the corpus listing.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <OpenImageIO/imagebuf.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path temp_dir() {
  fs::path d = fs::temp_directory_path() /
               ("aoeval_cli_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  fs::create_directories(d);
  return d;
}

Result run_with_env(const std::string& env, const std::string& args) {
  fs::path d = temp_dir();
  const std::string cmd = env + std::string(AOEVAL_BINARY) + " " + args + " >" +
                          (d / "stdout").string() + " 2>" + (d / "stderr").string() + " </dev/null";
  int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(d / "stdout");
  r.err = slurp(d / "stderr");
  return r;
}

Result run(const std::string& args) {
  return run_with_env("", args);
}

size_t lines(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

const char* kView = R"("views": [{"name": "main", "eye": [0, 1, 3], "target": [0, 0, 0]}])";

// Each bad scene: exit 2, one line on stderr naming the file and the field, no output file.
void expect_bad_scene(const std::string& file, const std::string& text, const std::string& field) {
  fs::path d = temp_dir();
  std::ofstream(d / file) << text;
  const fs::path out = d / "g.exr";
  fs::remove(out);
  Result r = run("gbuffer --scene " + (d / file).string() + " -o " + out.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(field), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename().string().find(".g.tmp"), std::string::npos)
        << "leftover temporary";
}

TEST(Cli, MisspelledKey) {
  expect_bad_scene(
      "typo.json",
      std::string(R"({"objects": [{"name": "p", "generator": "plane", "rol": "ground"}], )") +
          kView + "}",
      "objects[0].rol");
}

TEST(Cli, MissingMesh) {
  expect_bad_scene(
      "missing.json",
      std::string(R"({"objects": [{"name": "m", "mesh": "absent.off"}], )") + kView + "}",
      "objects[0].mesh");
}

TEST(Cli, NaNMesh) {
  fs::path d = temp_dir();
  std::ofstream(d / "nan.off") << "OFF\n3 1 0\n0 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n";
  expect_bad_scene("nanmesh.json",
                   std::string(R"({"objects": [{"name": "m", "mesh": "nan.off"}], )") + kView + "}",
                   "objects[0].mesh");
}

TEST(Cli, ZeroWidthView) {
  expect_bad_scene("zero.json", R"({"objects": [{"name": "p", "generator": "plane"}],
      "views": [{"name": "v", "eye": [0, 1, 3], "target": [0, 0, 0], "width": 0, "height": 10}]})",
                   "views[0].width");
}

TEST(Cli, BadUsageExitsTwo) {
  EXPECT_EQ(run("gbuffer --scene no-such-scene -o /tmp/aoeval_never.exr").code, 2);
  EXPECT_EQ(run("gbuffer --scene bunny --res 0x10 -o /tmp/aoeval_never.exr").code, 2);
  EXPECT_EQ(run("gbuffer --scene bunny --view nope -o /tmp/aoeval_never.exr").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("run --suite nope").code, 2);
  EXPECT_FALSE(fs::exists("/tmp/aoeval_never.exr"));
  EXPECT_EQ(run("--help").code, 0);
  EXPECT_EQ(run("gbuffer --help").code, 0);
}

TEST(Cli, GbufferWritesTheContractChannels) {
  const fs::path out = temp_dir() / "g.exr";
  Result r = run("gbuffer --scene cornell-box --res 64x48 -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  OIIO::ImageBuf image(out.string());
  ASSERT_TRUE(image.read());
  const auto& spec = image.spec();
  EXPECT_EQ(spec.width, 64);
  EXPECT_EQ(spec.height, 48);
  for (const char* c :
       {"A", "Z", "P.X", "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "Ng.X", "Ng.Y", "Ng.Z", "objectId"})
    EXPECT_GE(spec.channelindex(c), 0) << c;
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(spec.get_string_attribute("aoeval:scene"), "cornell-box");
  EXPECT_FALSE(spec.get_string_attribute("aoeval:view").empty());
  EXPECT_FALSE(spec.get_string_attribute("aoeval:version").empty());
}

TEST(Cli, ScenesListHasTheWholeCorpusAndABigEcosystem) {
  Result r = run("scenes list --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << "quiet when stderr is not a terminal: " << r.err;
  for (const char* n : {"sphere-uniform", "sphere-uniform-dense", "tree-apple", "tree-poplar",
                        "tree-ground", "grass-field", "ecosystem", "cornell-box", "room", "bunny",
                        "dragon", "armadillo", "elephant"})
    EXPECT_NE(r.out.find(std::string("\"") + n + "\""), std::string::npos) << n;
  const auto pos = r.out.find("\"ecosystem\"");
  ASSERT_NE(pos, std::string::npos);
  const auto tri = r.out.find("\"triangles\":", pos);
  ASSERT_NE(tri, std::string::npos);
  EXPECT_GE(std::stoll(r.out.substr(tri + 12)), 5000000ll);
}

TEST(Cli, ReferenceIsCachedAndCarriesItsHeader) {
  const fs::path d = temp_dir();
  fs::remove_all(d / "cache");
  const std::string env = "AOEVAL_CACHE=" + (d / "cache").string() + " ";
  const std::string args = "reference --scene cornell-box --res 32x32 --spp 16 --sampler sobol -o ";
  Result first = run_with_env(env, args + (d / "a.exr").string());
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_EQ(first.err.find("from cache"), std::string::npos) << first.err;
  Result second = run_with_env(env, args + (d / "b.exr").string());
  ASSERT_EQ(second.code, 0) << second.err;
  EXPECT_NE(second.err.find("served from cache"), std::string::npos) << second.err;
  EXPECT_EQ(slurp(d / "a.exr"), slurp(d / "b.exr"));
  Result uncached = run_with_env(env, args + (d / "c.exr").string() + " --no-cache");
  ASSERT_EQ(uncached.code, 0) << uncached.err;
  EXPECT_EQ(uncached.err.find("from cache"), std::string::npos);

  OIIO::ImageBuf image((d / "a.exr").string());
  ASSERT_TRUE(image.read());
  const auto& spec = image.spec();
  for (const char* c : {"AO", "AO_stderr", "bent.X", "bent.Y", "bent.Z", "A"})
    EXPECT_GE(spec.channelindex(c), 0) << c;
  for (const char* a :
       {"aoeval:scene", "aoeval:view", "aoeval:definition", "aoeval:spp", "aoeval:sampler",
        "aoeval:seed", "aoeval:estimator", "aoeval:params", "aoeval:version"})
    EXPECT_FALSE(spec.get_string_attribute(a).empty()) << a;
  EXPECT_EQ(spec.get_string_attribute("aoeval:sampler"), "sobol");
  EXPECT_EQ(spec.get_string_attribute("aoeval:spp"), "16");
}

TEST(Cli, ReferenceBadOptionsExitTwo) {
  const std::string out = (temp_dir() / "never.exr").string();
  for (const char* bad : {"--falloff linear", "--sampler halton", "--weighting area", "--dmax -1",
                          "--spp 0", "--normal bent", "--target-stderr 0.01 --max-spp 8"}) {
    Result r = run("reference --scene cornell-box --res 8x8 --no-cache " + std::string(bad) +
                   " -o " + out);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1u) << bad << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
