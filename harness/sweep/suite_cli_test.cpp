// `aoeval run` end to end on a tiny suite file (cornell-box at 40x40, a few rays): the report's
// path on stdout, a page that links every image and EXR the run kept (and nothing that is missing
// or external), results.csv/json rows, SQLite rows, kept earlier runs, and --set.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "harness/results/results_store.h"

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"

namespace {

namespace fs = std::filesystem;

using aoeval::cli_test::Result;
using aoeval::cli_test::slurp;

// The references go to a private cache; cornell-box needs no mesh from the data cache.
Result run(const fs::path& d, const std::string& args) {
  return aoeval::cli_test::run_aoeval("AOEVAL_CACHE=" + (d / "cache").string() + " ", args, d);
}

// Three estimators: constant and obscurances featured at their defaults, raytraced at its default
// plus a two-point sweep. obscurances scores against its own (bounded) definition, so the run
// keeps two references.
std::string write_suite(const fs::path& d) {
  const nlohmann::json suite =
      nlohmann::json::array({{{"name", "tiny"},
                              {"scenes", {"cornell-box"}},
                              {"res", {40, 40}},
                              {"reference", {{"spp", 16}, {"sampler", "sobol"}}},
                              {"timing", {{"warmup", 0}, {"repetitions", 2}}},
                              {"runs",
                               {{{"estimator", "constant"}},
                                {{"estimator", "raytraced"}, {"fixed", {{"rays", 4}}}},
                                {{"estimator", "raytraced"}, {"grid", {{"rays", {1, 2}}}}},
                                {{"estimator", "obscurances"}, {"fixed", {{"rays", 4}}}}}}}});
  std::ofstream(d / "tiny.json") << suite.dump(2);
  return (d / "tiny.json").string();
}

std::vector<std::string> attribute_values(const std::string& html, const std::string& attribute) {
  std::vector<std::string> values;
  const std::regex re(attribute + "=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), re); it != std::sregex_iterator();
       ++it)
    values.push_back((*it)[1]);
  return values;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

size_t data_lines(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  size_t n = 0;
  while (std::getline(in, line)) ++n;
  return n - 1;  // the header
}

TEST(SuiteCli, RunWritesAReportThatLinksEveryKeptFile) {
  const fs::path d = aoeval::testutil::test_temp_dir("suite_cli");
  const std::string suite = write_suite(d), out = (d / "out").string(),
                    db = (d / "r.sqlite").string();
  const Result r = run(d, "run --suite " + suite + " --out " + out + " --db " + db);
  ASSERT_EQ(r.code, 0) << r.err;
  // The last line on stdout is the report's path.
  EXPECT_EQ(r.out, (fs::path(out) / "index.html").string() + "\n");
  EXPECT_EQ(r.err.find('\033'), std::string::npos) << "no control characters when not a terminal";
  const std::string html = slurp(fs::path(out) / "index.html");
  ASSERT_FALSE(html.empty());

  // Every src and href is a relative path to a file that exists (no external URLs, no anchors to
  // nowhere).
  std::set<std::string> linked;
  for (const char* attribute : {"src", "href"})
    for (const auto& v : attribute_values(html, attribute)) {
      if (v.rfind("#", 0) == 0) {
        EXPECT_NE(html.find("id=\"" + v.substr(1) + "\""), std::string::npos) << v;
        continue;
      }
      EXPECT_EQ(v.find("://"), std::string::npos) << v;
      EXPECT_NE(v.front(), '/') << v;
      EXPECT_TRUE(fs::exists(fs::path(out) / v)) << v;
      linked.insert(v);
    }
  // Scripts are the page's own (viewer/, checked above as src); the viewers' data scripts exist.
  EXPECT_EQ(count(html, "<script"), count(html, "<script src=\"viewer/"));
  for (const char* attribute : {"data-a", "data-b"})
    for (const auto& v : attribute_values(html, attribute))
      EXPECT_TRUE(fs::exists(fs::path(out) / v)) << v;
  EXPECT_EQ(attribute_values(html, "data-b").size(), 3u) << "a viewer per mosaic";
  // ... and every image and EXR the run kept is on the page.
  size_t kept = 0;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    const std::string ext = e.path().extension().string();
    const std::string rel = fs::relative(e.path(), out).string();
    if (rel.rfind("gbuffers/", 0) == 0 || (ext != ".png" && ext != ".exr")) continue;
    ++kept;
    EXPECT_TRUE(linked.count(rel)) << rel << " is not on the page";
  }
  // 5 estimates + 3 mosaics + 3 charts + 2 references.
  EXPECT_EQ(kept, 13u);
  EXPECT_EQ(count(html, "<img class=\"mosaic\""), 3u);
  EXPECT_EQ(count(html, "<img class=\"chart\""), 3u);
  EXPECT_TRUE(fs::exists(fs::path(out) / "gbuffers" / "index.html"));

  // Rows: constant, raytraced rays 4, 1, 2, obscurances.
  EXPECT_EQ(data_lines(fs::path(out) / "results.csv"), 5u);
  const auto json = nlohmann::json::parse(slurp(fs::path(out) / "results.json"));
  ASSERT_EQ(json["rows"].size(), 5u);
  const std::string run_id = json["context"]["run_id"];
  EXPECT_EQ(json["context"]["output_dir"], fs::weakly_canonical(out).string());
  for (const auto& row : json["rows"]) {
    EXPECT_EQ(row["status"], "ok");
    EXPECT_EQ(row["run_id"], run_id);
    const std::string estimate = row["estimate_file"];
    EXPECT_EQ(estimate.rfind("runs/" + run_id + "/estimates/", 0), 0u) << estimate;
    EXPECT_TRUE(fs::exists(fs::path(out) / estimate)) << estimate;
  }
  aoeval::SqliteStore store(db);
  EXPECT_EQ(store.rows_of_run(run_id).size(), 5u);
  // The finished context (its time by stage, the page's included, measured after the page was
  // written) is in both results.json files and the history, recorded by the run's recorder.
  const auto run_json =
      nlohmann::json::parse(slurp(fs::path(out) / "runs" / run_id / "results.json"));
  for (const nlohmann::json& context : {json["context"], run_json["context"]}) {
    EXPECT_TRUE(context["stages_ms"].contains("report (page, plots)")) << context;
    EXPECT_GT(context["stages_ms"].value("wall", 0.0), 0.0) << context;
  }
  EXPECT_EQ(run_json["rows"].size(), 5u);
  // A fresh folder's two results.json are the same bytes: one file, hard-linked.
  EXPECT_TRUE(fs::equivalent(fs::path(out) / "results.json",
                             fs::path(out) / "runs" / run_id / "results.json"));
  const std::string first_runs_copy = slurp(fs::path(out) / "runs" / run_id / "results.json");
  const auto runs = store.runs();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].run_id, run_id);
  EXPECT_TRUE(runs[0].stages_ms.contains("report (page, plots)")) << runs[0].stages_ms;

  // A second run keeps the first one's images and adds its rows to the history.
  const Result again = run(d, "run --suite " + suite + " --out " + out + " --db " + db);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(fs::exists(fs::path(out) / "runs" / run_id / "estimates"));
  // ... and its own results.json as it was, though the folder's was rewritten.
  EXPECT_FALSE(fs::equivalent(fs::path(out) / "results.json",
                              fs::path(out) / "runs" / run_id / "results.json"));
  EXPECT_EQ(slurp(fs::path(out) / "runs" / run_id / "results.json"), first_runs_copy);
  EXPECT_EQ(store.all_rows().size(), 10u);
  EXPECT_EQ(data_lines(fs::path(out) / "results.csv"), 5u) << "the newest run's rows";
}

TEST(SuiteCli, SetOverridesAnEstimatorsValuesOrNamesTheMistake) {
  const fs::path d = aoeval::testutil::test_temp_dir("suite_cli");
  const std::string suite = write_suite(d), out = (d / "out").string(),
                    db = (d / "r.sqlite").string();
  const std::string base = "run --suite " + suite + " --out " + out + " --db " + db;
  const Result r = run(d, base + " --set raytraced:rays=3");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto json = nlohmann::json::parse(slurp(fs::path(out) / "results.json"));
  std::vector<std::string> names;
  for (const auto& row : json["rows"]) names.push_back(row["run_name"]);
  EXPECT_EQ(names,
            (std::vector<std::string>{"constant/scene:cornell-box/view:main/40x40",
                                      "raytraced/rays:3/scene:cornell-box/view:main/40x40",
                                      "obscurances/rays:4/scene:cornell-box/view:main/40x40"}));

  for (const auto& [set, named] :
       std::vector<std::pair<std::string, std::string>>{{"nope:rays=2", "nope"},
                                                        {"raytraced:rayz=2", "rayz"},
                                                        {"tree-sphere:alpha_rho=2", "tree-sphere"},
                                                        {"raytraced", "ESTIMATOR:KEY=VALUE"}}) {
    const Result bad = run(d, base + " --set " + set);
    EXPECT_EQ(bad.code, 2) << set << ": " << bad.err;
    EXPECT_NE(bad.err.find(named), std::string::npos) << set << ": " << bad.err;
  }
  EXPECT_EQ(run(d, "run --suite nosuch --out " + out).code, 2);
}

}  // namespace
