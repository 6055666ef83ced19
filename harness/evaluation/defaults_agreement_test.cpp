// One declaration per default, proved for every registered estimator (STYLE "Every parameter is
// declared once"): the defaults `aoeval estimators show --json` prints, the values the estimator
// reads when it is created and run (ParamSet::read_names: every declared parameter must be read
// from the set, none fixed in code), and the aoeval:params attribute of the EXR `aoeval estimate`
// writes all equal the parameter table's defaults.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <fstream>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"
#include "estimators/registry.h"
#include "estimators/testing/registry_test_names.h"
#include "scenes/analytic_scenes.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"

namespace aoeval {
namespace {

using cli_test::run_aoeval;

class DefaultsAgree : public ::testing::TestWithParam<std::string> {
 protected:
  const EstimatorInfo& info() const { return find_estimator(GetParam()); }
};

nlohmann::json table_defaults(const EstimatorInfo& e) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& p : e.params) j[p.name] = p.default_value;
  return j;
}

TEST_P(DefaultsAgree, EstimatorsShowPrintsTheTable) {
  const EstimatorInfo& e = info();
  const auto dir = testutil::test_temp_dir("defaults");
  const auto r = run_aoeval("", "estimators show " + e.name + " --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json shown = nlohmann::json::parse(r.out);
  nlohmann::json defaults = nlohmann::json::object();
  for (const auto& p : shown["params"]) defaults[p["name"].get<std::string>()] = p["default"];
  EXPECT_EQ(defaults, table_defaults(e)) << e.name;
}

// The parameters the estimator reads when the harness makes and runs it: each declared one, at its
// default (the set holds the table's defaults, so a parameter read from it cannot drift; one that
// is never read is a value fixed somewhere in code instead).
TEST_P(DefaultsAgree, RunTimeSettingsAreTheTable) {
  const EstimatorInfo& e = info();
  const ParamSet params = default_params(e);
  EXPECT_EQ(params.json(), table_defaults(e)) << e.name;
  e.definition(params);
  std::unique_ptr<Estimator> est = e.create(params);
  Scene scene = scene_of({generated("floor", "plane", {{"size", {2, 2}}})});
  scene.views.front().eye = {0, 1, 1.5f};
  EmbreeScene es(scene);
  const GBuffer g = render_gbuffer(es, make_camera(scene.views.front(), 16, 12));
  const EstimateContext context{scene, es, g};
  try {
    est->prepare(context);
    est->run(context);
  } catch (const EstimatorUnavailable&) {
    // The backend is missing here: what create() and definition() read is still checked.
  }
  const std::set<std::string> read = params.read_names();
  for (const auto& p : e.params)
    EXPECT_TRUE(read.count(p.name))
        << e.name << ": parameter " << p.name << " (default " << p.default_value.dump()
        << ") is declared but never read at run time: its value is fixed in code";
}

TEST_P(DefaultsAgree, EstimateExrParamsAreTheTable) {
  const EstimatorInfo& e = info();
  const auto dir = testutil::test_temp_dir("defaults");
  // A small tree above a ground plane, so the tree estimators have something to derive.
  const std::string scene = (dir / "scene.json").string();
  {
    std::ofstream f(scene);
    f << R"({"objects": [
      {"name": "ground", "generator": "plane", "role": "ground", "params": {"size": [4, 4]}},
      {"name": "crown", "generator": "sphere-uniform", "seed": 3, "role": "tree",
       "params": {"count": 800, "radius": 0.5, "triangle_size": 0.08},
       "transform": {"translate": [0, 0.9, 0]}}],
     "views": [{"name": "main", "eye": [0, 0.8, 2.5], "target": [0, 0.5, 0], "fov_y_deg": 50,
                "width": 24, "height": 18}]})";
  }
  const std::string exr = (dir / "estimate.exr").string();
  const auto r =
      run_aoeval("", "estimate --estimator " + e.name + " --scene " + scene + " -o " + exr, dir);
  if (r.code == 1 && r.err.find("skipped") != std::string::npos)
    GTEST_SKIP() << e.name << ": " << r.err;
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  OIIO::ImageBuf image(exr);
  ASSERT_TRUE(image.init_spec(exr, 0, 0)) << image.geterror();
  nlohmann::json written =
      nlohmann::json::parse(image.spec().get_string_attribute("aoeval:params"));
  written.erase("derived");  // what prepare() derived from the scene, not a parameter
  EXPECT_EQ(written, table_defaults(e)) << e.name;
}

AOEVAL_INSTANTIATE_OVER_REGISTRY(DefaultsAgree);

}  // namespace
}  // namespace aoeval
