// The headless Vulkan layer of aoeval (issue #6): one instance, one physical device, one queue that
// does compute and graphics, a command pool. No window, no swapchain; everything runs off-screen
// and works on Mesa lavapipe (the CPU "llvmpipe" device) as on a real GPU.
//
// Device choice: Options::device, else $AOEVAL_VK_DEVICE, else the first discrete GPU, else the
// first integrated GPU, else any other device (lavapipe is a CPU device). A selector is a device
// index ("0", "1", ...) or a case-insensitive substring of the device name ("llvmpipe", "nvidia").
//
// Validation: VK_LAYER_KHRONOS_validation and a debug messenger in Debug builds (and whenever
// $AOEVAL_VK_VALIDATION=1 or Options::validation asks for it) when the layer is installed. Error
// messages are collected and thrown as VulkanError by the next submit() (and by
// throw_if_validation_errors()), so a validation error fails the test or run that caused it.
//
// Typical use (an estimator's prepare()/run()):
//   vk::Context& vk = vk::require_shared_context();   // throws EstimatorUnavailable if none
//   vk.submit([&](VkCommandBuffer cmd) { ... record passes ... });   // submits and waits
#pragma once

#include <vulkan/vulkan.h>

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace aoeval::vk {

// A Vulkan call failed (with its VkResult) or the validation layer reported errors.
class VulkanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A zeroed Vulkan create-info struct with its sType set: `auto info =
// make_info<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);` (the usual `T x{sType}`
// trips -Wmissing-field-initializers, which our warning flags turn on).
template <class T>
T make_info(VkStructureType type) {
  T value{};
  value.sType = type;
  return value;
}

// Throws VulkanError("<what>: VK_ERROR_...") unless result is VK_SUCCESS.
void check(VkResult result, const char* what);
const char* result_name(VkResult result);

struct ContextOptions {
  // Device selector (index or name substring); empty: $AOEVAL_VK_DEVICE, else the default choice.
  std::string device;
  // Validation layer on/off; unset: on in Debug builds or when $AOEVAL_VK_VALIDATION=1. Ignored
  // (with validation_enabled() false) when the layer is not installed.
  std::optional<bool> validation;
};

class Context {
 public:
  // A context, or nullptr with `reason` set to one human line saying why there is no usable device
  // (no loader/ICD, instance creation failed, no device, selector matching none: the reason then
  // lists the devices found). Never throws for a missing device.
  static std::unique_ptr<Context> create(const ContextOptions& options, std::string* reason);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  // "llvmpipe (LLVM 15.0.6, 256 bits)", the results' `device` column.
  const std::string& device_name() const { return device_name_; }
  // Device name, type and driver, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) [cpu, Mesa 22.3.6]".
  std::string device_description() const;
  // Nanoseconds per timestamp tick; timestamps_supported() is false when the queue has none.
  float timestamp_period_ns() const { return properties_.limits.timestampPeriod; }
  bool timestamps_supported() const { return timestamp_valid_bits_ > 0; }
  uint32_t timestamp_valid_bits() const { return timestamp_valid_bits_; }
  bool validation_enabled() const { return validation_; }

  // A memory type index with these properties among `type_bits`; throws VulkanError if none.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags properties) const;

  // Records commands into a fresh primary command buffer, submits it to the queue and waits for
  // it. Serialised by a mutex (the queue and pool are shared); may nest (a record callback may
  // create images, which submit their own initialisation first). Throws VulkanError on failure or
  // when the validation layer reported errors meanwhile.
  void submit(const std::function<void(VkCommandBuffer)>& record);

  // An object kept for the context's lifetime under `key`, made by `make` on first use and
  // released before the device is destroyed (ComputePipeline's compiled pipelines, shared by every
  // pipeline made from the same code: issue 42). Thread-safe.
  std::shared_ptr<void> kept(const std::string& key,
                             const std::function<std::shared_ptr<void>()>& make);

  // Validation errors seen so far (and not yet thrown), and the throw that reports them.
  std::vector<std::string> validation_errors() const;
  void throw_if_validation_errors();

 private:
  Context() = default;
  friend struct ContextBuilder;
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(
      VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  uint32_t timestamp_valid_bits_ = 0;
  std::string device_name_;
  std::string driver_info_;
  bool validation_ = false;
  mutable std::recursive_mutex submit_mutex_;  // recursive: recording may create images
  mutable std::mutex messages_mutex_;
  std::vector<std::string> validation_errors_;
  std::mutex kept_mutex_;
  std::map<std::string, std::shared_ptr<void>> kept_;
};

// The devices the loader sees, "0: llvmpipe (...) [cpu]" one per entry; empty with `reason` set
// when there is no loader, ICD or device.
std::vector<std::string> list_devices(std::string* reason);

// The process-wide context, created on first use with default options (so $AOEVAL_VK_DEVICE and
// $AOEVAL_VK_VALIDATION apply). nullptr when there is no usable device, with the reason in
// `reason`; the answer is cached for the process. It lives until exit: objects made from it
// (buffers, images, pipelines) belong to estimators and must die before it, so never keep them in
// statics.
Context* shared_context(std::string* reason = nullptr);

// The shared context, or throws aoeval::EstimatorUnavailable("no Vulkan device (<reason>)"): what
// a Vulkan estimator calls in prepare()/run().
Context& require_shared_context();

}  // namespace aoeval::vk
