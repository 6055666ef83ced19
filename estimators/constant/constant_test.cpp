// constant: AO = value on every pixel, whatever the scene, through its declaration.
#include "estimators/constant/constant.h"

#include <gtest/gtest.h>

#include "base/errors.h"
#include "scenes/analytic_scenes.h"

namespace aoeval {
namespace {

std::vector<float> run_constant(const nlohmann::json& overrides) {
  const EstimatorInfo e = constant_estimator();
  Scene s = scene_of({generated("box", "box", {{"size", {2, 2, 2}}, {"inward", true}})});
  EmbreeScene es(s);
  const GBuffer g = probe({0, -1, 0}, {0, 1, 0}, 12);
  auto est = e.create(resolve_params(e.name, e.params, overrides, "test"));
  return est->run({s, es, g}).ao;
}

TEST(Constant, EveryPixelGetsTheValue) {
  for (double v : {0.0, 0.25, 1.0}) {
    const std::vector<float> ao = run_constant({{"value", v}});
    ASSERT_EQ(ao.size(), 12u);
    for (float a : ao) EXPECT_EQ(a, static_cast<float>(v));
  }
  // At its default (1: ambient light only) even inside a closed box.
  for (float a : run_constant(nlohmann::json::object())) EXPECT_EQ(a, 1.0f);
}

TEST(Constant, ValuesOutsideTheUnitIntervalAreInputErrors) {
  EXPECT_THROW(run_constant({{"value", 1.5}}), InputError);
  EXPECT_THROW(run_constant({{"value", -0.1}}), InputError);
  EXPECT_THROW(run_constant({{"valeu", 0.5}}), InputError);
}

}  // namespace
}  // namespace aoeval
