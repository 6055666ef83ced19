// Recording helpers: barriers between passes and GPU timestamps per named pass.
//
//   vk::PassTimer timer(vk);
//   vk.submit([&](VkCommandBuffer cmd) {
//     timer.reset(cmd);
//     timer.begin(cmd, "horizon");  horizon.dispatch(...);  timer.end(cmd);
//     vk::pass_barrier(cmd);
//     timer.begin(cmd, "blur");     blur.dispatch(...);     timer.end(cmd);
//   });
//   result.pass_ms = timer.read();   // {"horizon_ms": ..., "blur_ms": ..., "total_ms": ...}
#pragma once

#include <vulkan/vulkan.h>

#include <map>
#include <string>
#include <vector>

#include "estimators/vulkan/vk_context.h"

namespace aoeval::vk {

// Every write of earlier commands (shaders, attachments, copies) is visible to every read or write
// of later ones. Coarse but always correct; between AO passes the cost is negligible.
void pass_barrier(VkCommandBuffer cmd);

// Named GPU time spans from timestamp queries, converted with the device's timestampPeriod.
class PassTimer {
 public:
  explicit PassTimer(Context& context, uint32_t max_passes = 16);
  ~PassTimer();
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

  // Resets the query pool and forgets earlier passes; record it first in each command buffer.
  void reset(VkCommandBuffer cmd);
  // Timestamps around a pass: begin() after all earlier commands finished, end() after the pass's
  // commands finished (both at BOTTOM_OF_PIPE, so a pass's span covers its own work). On lavapipe
  // a dispatch pass's begin timestamp needs a flush of its own (write_timestamp says why); a pass
  // of draws does not (its draws are queued after the timestamp, like the timestamp itself).
  // Work::unflushed_dispatches skips that flush for a dispatch that reads what draws just wrote:
  // shadowmap-ao's accumulation, whose frames the flush made 2 to 4 times slower on lavapipe
  // (measured: 2.6 s against 4.9 and 10.3 s on bunny). Its span may then be counted in the pass
  // before it; the submission's total_ms stays exact as long as it begins with draws.
  enum class Work { dispatches, draws, unflushed_dispatches };
  void begin(VkCommandBuffer cmd, const std::string& pass, Work work = Work::dispatches);
  void end(VkCommandBuffer cmd);
  // After the submission finished: "<pass>_ms" per pass (a pass recorded twice sums), and
  // "total_ms" from the first begin to the last end. Empty when timestamps are unsupported.
  std::map<std::string, double> read() const;

 private:
  void write_timestamp(VkCommandBuffer cmd, uint32_t query, bool flush);

  Context& context_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t capacity_ = 0;  // timestamps read (two per pass); the pool holds twice as many
  std::vector<std::string> passes_;
  bool open_ = false;
};

}  // namespace aoeval::vk
