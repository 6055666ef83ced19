#include "estimators/registry.h"

#include "errors.h"
#include "estimators/constant/constant.h"
#include "estimators/gtao/gtao.h"
#include "estimators/hbao_split/hbao_split.h"
#include "estimators/hbao_split/hbao_vulkan.h"
#include "estimators/obscurances/obscurances.h"
#include "estimators/raymarch_ssao/raymarch_ssao.h"
#include "estimators/raytraced/raytraced.h"
#include "estimators/reeves_blau/reeves_blau.h"
#include "estimators/shadowmap_ao/shadowmap_ao.h"
#include "estimators/tree_hegeman/tree_hegeman.h"
#include "estimators/vertex_baked/vertex_baked.h"
#include "estimators/vulkan/vk_context.h"

namespace aoeval {

const std::vector<EstimatorInfo>& estimator_registry() {
  // One line per estimator. The calls reference each folder's symbols directly, so the linker
  // keeps them all.
  // clang-format off
  static const std::vector<EstimatorInfo> registry = {
      constant_estimator(),
      raytraced_estimator(),
      obscurances_estimator(),
      vertex_baked_estimator(),
      tree_sphere_estimator(), tree_ellipsoid_estimator(), tree_shells_estimator(),
      reeves_blau_estimator(),
      hbao_split_estimator(),
      hbao_split_cpu_estimator(),
      raymarch_ssao_estimator(),
      gtao_estimator(),
      gtao_cpu_estimator(),
      shadowmap_ao_estimator(),
  };
  // clang-format on
  return registry;
}

const EstimatorInfo& find_estimator(const std::string& name) {
  std::string known;
  for (const auto& e : estimator_registry()) {
    if (e.name == name) return e;
    known += (known.empty() ? "" : ", ") + e.name;
  }
  throw InputError("--estimator: unknown estimator '" + name + "' (estimators: " + known + ")");
}

std::string backend_device(Backend b) {
  if (b != Backend::vulkan) return "";
  const vk::Context* context = vk::shared_context();
  return context ? context->device_description() : "";
}

}  // namespace aoeval
