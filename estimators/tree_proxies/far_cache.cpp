#include "estimators/tree_proxies/far_cache.h"

#include <atomic>
#include <cstring>
#include <list>
#include <mutex>
#include <type_traits>
#include <utility>

namespace aoeval {
namespace {

// Four: the tree estimators (sphere, ellipsoid, shells, volume) each derive their own occluders,
// so a suite that runs all four over one forest sequence reuses four fields.
constexpr size_t kCapacity = 4;

struct Entry {
  FarFieldsInput input;
  std::shared_ptr<const FarFields> fields;
};

std::mutex cache_mutex;
std::list<Entry> cache;  // most recently used first
std::atomic<size_t> builds{0};

bool same_bytes(const std::vector<hegeman::UnitMap>& a, const std::vector<hegeman::UnitMap>& b) {
  static_assert(std::is_trivially_copyable_v<hegeman::UnitMap>);
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(hegeman::UnitMap)) == 0);
}

std::shared_ptr<const FarFields> find(const FarFieldsInput& input) {
  for (auto it = cache.begin(); it != cache.end(); ++it)
    if (it->input == input) {
      cache.splice(cache.begin(), cache, it);
      return it->fields;
    }
  return nullptr;
}

}  // namespace

bool FarFieldsInput::operator==(const FarFieldsInput& other) const {
  return same_bytes(occluders, other.occluders) && region.lower == other.region.lower &&
         region.upper == other.region.upper && cull == other.cull && angle == other.angle &&
         cell == other.cell && near == other.near && horizon == other.horizon;
}

std::shared_ptr<const FarFields> shared_far_fields(const FarFieldsInput& input) {
  {
    std::lock_guard<std::mutex> lock(cache_mutex);
    if (auto hit = find(input)) return hit;
  }
  // Built without the lock: the grid's build runs TBB loops, and a worker that steals another
  // point's prepare while this thread held the lock would wait on itself.
  auto fields = std::make_shared<FarFields>();
  fields->far.build(input.occluders, input.cull, input.angle);
  fields->grid.build(input.occluders, fields->far, input.region, input.cell, input.near,
                     input.horizon);
  ++builds;
  std::lock_guard<std::mutex> lock(cache_mutex);
  if (auto raced = find(input)) return raced;
  cache.push_front({input, fields});
  if (cache.size() > kCapacity) cache.pop_back();
  return fields;
}

size_t far_fields_builds() {
  return builds.load();
}

}  // namespace aoeval
