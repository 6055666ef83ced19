#include "estimators/vulkan/vk_commands.h"

#include <algorithm>

namespace aoeval::vk {

void pass_barrier(VkCommandBuffer cmd) {
  auto m = make_info<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  m.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  m.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       0, 1, &m, 0, nullptr, 0, nullptr);
}

PassTimer::PassTimer(Context& context, uint32_t max_passes)
    : context_(context), capacity_(2 * max_passes) {
  if (!context.timestamps_supported()) return;
  auto info = make_info<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * capacity_;  // each timestamp has a flush sibling (write_timestamp)
  check(vkCreateQueryPool(context.device(), &info, nullptr, &pool_), "vkCreateQueryPool");
}

PassTimer::~PassTimer() {
  if (pool_) vkDestroyQueryPool(context_.device(), pool_, nullptr);
}

void PassTimer::reset(VkCommandBuffer cmd) {
  passes_.clear();
  open_ = false;
  if (pool_) vkCmdResetQueryPool(cmd, pool_, 0, 2 * capacity_);
}

void PassTimer::begin(VkCommandBuffer cmd, const std::string& pass, Work work) {
  if (open_) throw VulkanError("PassTimer: begin(\"" + pass + "\") inside an open pass");
  if (2 * (passes_.size() + 1) > capacity_)
    throw VulkanError("PassTimer: more than " + std::to_string(capacity_ / 2) + " passes");
  open_ = true;
  passes_.push_back(pass);
  write_timestamp(cmd, static_cast<uint32_t>(2 * (passes_.size() - 1)), work == Work::dispatches);
}

void PassTimer::end(VkCommandBuffer cmd) {
  if (!open_) throw VulkanError("PassTimer: end() without begin()");
  open_ = false;
  // An end timestamp is written by the flush before the next command's timestamp or at the end of
  // the submission, both after the pass: it needs no flush of its own.
  write_timestamp(cmd, static_cast<uint32_t>(2 * passes_.size() - 1), false);
}

void PassTimer::write_timestamp(VkCommandBuffer cmd, uint32_t query, bool flush) {
  if (!pool_) return;
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, query);
  if (!flush) return;
  // The sibling write, whose value is never read, makes the timestamp above land now on lavapipe.
  // (Only begin timestamps of dispatch passes ask for it: see PassTimer::Work.)
  // lavapipe flushes queued work before a BOTTOM_OF_PIPE timestamp and then queues the timestamp;
  // once a raster pass has bound a framebuffer in the context, llvmpipe writes a queued timestamp
  // only at the next flush. Without the sibling a pass's begin timestamp landed after the pass's
  // compute dispatch: a GLSL plug-in measured 0.01 ms for a 31 ms frame (the submit's CPU wall
  // time) when gtao's raster G-buffer had run before it in the same process. The sibling's own
  // flush writes the timestamp before the pass starts. Elsewhere it is one more timestamp write.
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, capacity_ + query);
}

std::map<std::string, double> PassTimer::read() const {
  std::map<std::string, double> ms;
  if (!pool_ || passes_.empty()) return ms;
  if (open_) throw VulkanError("PassTimer: read() with a pass still open");
  const uint32_t count = static_cast<uint32_t>(2 * passes_.size());
  std::vector<uint64_t> ticks(count);
  check(vkGetQueryPoolResults(context_.device(), pool_, 0, count, count * sizeof(uint64_t),
                              ticks.data(), sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  // Only timestampValidBits are meaningful; differences are taken modulo that width.
  const uint32_t bits = context_.timestamp_valid_bits();
  const uint64_t mask = bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
  const double ns_per_tick = context_.timestamp_period_ns();
  auto span_ms = [&](uint64_t a, uint64_t b) {
    return static_cast<double>((b - a) & mask) * ns_per_tick * 1e-6;
  };
  for (size_t p = 0; p < passes_.size(); ++p)
    ms[passes_[p] + "_ms"] += span_ms(ticks[2 * p], ticks[2 * p + 1]);
  ms["total_ms"] = span_ms(ticks.front(), ticks.back());
  return ms;
}

}  // namespace aoeval::vk
