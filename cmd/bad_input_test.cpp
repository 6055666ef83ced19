// The bad-input corpus (issue 15): one table-driven test over
// harness/testdata/bad_input/cases.json. Every case is input a hostile or careless user could give;
// each must exit with the code the table says (2: bad input), print exactly one line on stderr that
// names the file and the field, leave no output behind and leave every input byte-identical (a
// rejected database is not converted or extended). To add a case: drop its input file into the
// folder and add a line to the table.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "base/input_limits.h"
#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"

namespace {

namespace fs = std::filesystem;
using aoeval::cli_test::slurp;

const fs::path kCorpus = fs::path(AOEVAL_SOURCE_DIR) / "harness/testdata/bad_input";

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

size_t line_count(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// Writes the inputs that are generated rather than committed; false when the case cannot apply
// on this machine (said in the test's output).
bool generate(const std::string& what, const fs::path& in) {
  if (what == "deep_scene") {
    // 100,000 nested arrays: parsed iteratively by nlohmann, but any recursive walk of the value
    // (a copy, a dump) would overflow the stack.
    std::ofstream(in / "deep.json") << std::string(100000, '[') << std::string(100000, ']');
  } else if (what == "symlink_loop") {
    std::error_code ec;
    fs::create_symlink("loop.json", in / "loop.json", ec);
  } else if (what == "foreign_sqlite") {
    sqlite3* db = nullptr;
    sqlite3_open((in / "foreign.sqlite").c_str(), &db);
    sqlite3_exec(db, "CREATE TABLE notes (id INTEGER PRIMARY KEY, text TEXT)", nullptr, nullptr,
                 nullptr);
    sqlite3_exec(db, "INSERT INTO notes (text) VALUES ('not aoeval''s')", nullptr, nullptr,
                 nullptr);
    sqlite3_close(db);
  } else if (what == "ao_exrs") {
    // Two small AO images: one well formed, one whose aoeval:definition header is not JSON.
    // And negative.exr: well formed, but AO = -5 at pixel (3, 2).
    for (const auto& [file, definition] :
         {std::pair<std::string, std::string>{"good.exr", R"({"weighting": "cosine"})"},
          {"baddef.exr", "{not json"},
          {"negative.exr", R"({"weighting": "cosine"})"}}) {
      OIIO::ImageSpec spec(8, 8, 2, OIIO::TypeDesc::FLOAT);
      spec.channelnames = {"AO", "A"};
      spec.attribute("aoeval:definition", definition);
      OIIO::ImageBuf image(spec);
      const float pixel[2] = {0.5f, 1.0f};
      OIIO::ImageBufAlgo::fill(image, pixel);
      if (file == "negative.exr") {
        const float bad[2] = {-5.0f, 1.0f};
        image.setpixel(3, 2, bad);
      }
      image.write((in / file).string());
    }
  } else if (what == "same_name_scenes") {
    // Two different scene files both called floor.json: their rows would share every run name.
    const char* scene =
        R"({"objects": [{"name": "f", "generator": "plane", "params": {"size": [%d, 2]}}],
            "views": [{"name": "main", "eye": [0, 1, 3], "target": [0, 0, 0]}]})";
    for (int k : {1, 2}) {
      // Appended, not "s" + to_string(k): GCC 12 warns falsely on that (-Wrestrict, PR 105329).
      std::string sub(1, 's');
      sub += std::to_string(k);
      fs::create_directories(in / sub);
      char text[512];
      std::snprintf(text, sizeof text, scene, k + 1);
      std::ofstream(in / sub / "floor.json") << text;
    }
    std::ofstream(in / "sweep_same_name.json")
        << R"({"name": "same-name", "scenes": [")" << (in / "s1/floor.json").string() << R"(", ")"
        << (in / "s2/floor.json").string()
        << R"("], "res": [16, 16], "runs": [{"estimator": "constant"}]})";
  } else if (what == "needs_less_memory_than_16384x16384") {
    const double needed = 16384.0 * 16384.0 * aoeval::kBytesPerPixelBudget;
    return aoeval::available_memory_bytes() != 0 &&
           static_cast<double>(aoeval::available_memory_bytes()) < needed;
  }
  return true;
}

std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_symlink()) {
      files[e.path().filename().string()] = "-> " + fs::read_symlink(e.path()).string();
    } else if (e.is_regular_file()) {
      files[e.path().filename().string()] = slurp(e.path());
    }
  }
  return files;
}

TEST(BadInput, EveryCaseOfTheCorpusIsRejectedCleanly) {
  const nlohmann::json table = nlohmann::json::parse(slurp(kCorpus / "cases.json"));
  const fs::path root = aoeval::testutil::test_temp_dir("bad_input");
  const std::string env = "AOEVAL_CACHE=" + (root / "cache").string() + " ";
  size_t ran = 0;
  for (const auto& c : table["cases"]) {
    const std::string name = c["name"];
    SCOPED_TRACE(name);
    const fs::path in = root / "in", out = root / "out", capture = root / "capture";
    for (const auto& d : {in, out, capture}) {
      fs::remove_all(d);
      fs::create_directories(d);
    }
    fs::copy(kCorpus, in, fs::copy_options::recursive);
    if (c.contains("generated") && !generate(c["generated"], in)) {
      std::printf("[ skipped  ] %s: does not apply on this machine\n", name.c_str());
      continue;
    }
    const auto before = snapshot(in);
    std::string args = replace_all(c["args"], "{in}", in.string());
    args = replace_all(args, "{out}", out.string());
    const std::string case_env =
        c.contains("env") ? replace_all(c["env"], "{in}", in.string()) + " " : "";
    const auto r = aoeval::cli_test::run_aoeval(env + case_env, args, capture);
    ++ran;
    EXPECT_EQ(r.code, c["exit"].get<int>()) << args << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    for (const auto& s : c["stderr_has"])
      EXPECT_NE(r.err.find(s.get<std::string>()), std::string::npos)
          << "stderr does not name '" << s.get<std::string>() << "': " << r.err;
    EXPECT_TRUE(fs::is_empty(out))
        << "left output behind: " << (*fs::directory_iterator(out)).path();
    EXPECT_EQ(snapshot(in), before) << "an input was modified, or a file was added beside it";
  }
  std::printf("bad-input corpus: %zu of %zu cases ran\n", ran, table["cases"].size());
  EXPECT_GE(ran, table["cases"].size() - 1);
}

}  // namespace
