#include "estimators/vulkan/vk_context.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include "estimators/estimator.h"

namespace aoeval::vk {

const char* result_name(VkResult result) {
  switch (result) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
    case VK_NOT_READY:
      return "VK_NOT_READY";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    case VK_INCOMPLETE:
      return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
      return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
      return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
      return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_OUT_OF_POOL_MEMORY:
      return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default:
      return "VkResult (other)";
  }
}

void check(VkResult result, const char* what) {
  if (result == VK_SUCCESS) return;
  std::string message(what);
  message.append(": ")
      .append(result_name(result))
      .append(" (")
      .append(std::to_string(static_cast<int>(result)) + ")");
  throw VulkanError(message);
}

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool env_flag(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && std::strcmp(v, "1") == 0;
}

bool validation_layer_present() {
  uint32_t count = 0;
  if (vkEnumerateInstanceLayerProperties(&count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(count);
  if (vkEnumerateInstanceLayerProperties(&count, layers.data()) != VK_SUCCESS) return false;
  return std::any_of(layers.begin(), layers.end(),
                     [](const auto& l) { return std::strcmp(l.layerName, kValidationLayer) == 0; });
}

bool debug_utils_present() {
  uint32_t count = 0;
  if (vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> exts(count);
  if (vkEnumerateInstanceExtensionProperties(nullptr, &count, exts.data()) != VK_SUCCESS)
    return false;
  return std::any_of(exts.begin(), exts.end(), [](const auto& e) {
    return std::strcmp(e.extensionName, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) == 0;
  });
}

const char* type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    default:
      return "other";
  }
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// A queue family with graphics and compute, or -1.
int universal_queue_family(VkPhysicalDevice d) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(d, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(d, &count, families.data());
  const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
  for (uint32_t i = 0; i < count; ++i)
    if ((families[i].queueFlags & need) == need) return static_cast<int>(i);
  return -1;
}

// Instance creation shared by Context::create and list_devices; VK_NULL_HANDLE + reason on failure.
VkInstance make_instance(bool validation, bool debug_utils, std::string* reason) {
  auto app = make_info<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "aoeval";
  app.apiVersion = VK_API_VERSION_1_1;
  auto info = make_info<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &app;
  const char* layers[] = {kValidationLayer};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
  if (validation) {
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = layers;
  }
  if (debug_utils) {
    info.enabledExtensionCount = 1;
    info.ppEnabledExtensionNames = extensions;
  }
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult r = vkCreateInstance(&info, nullptr, &instance);
  if (r != VK_SUCCESS) {
    if (reason)
      *reason = std::string("vkCreateInstance failed: ") + result_name(r) +
                (r == VK_ERROR_INCOMPATIBLE_DRIVER ? " (no Vulkan driver/ICD found)" : "");
    return VK_NULL_HANDLE;
  }
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t count = 0;
  if (vkEnumeratePhysicalDevices(instance, &count, nullptr) != VK_SUCCESS) return {};
  std::vector<VkPhysicalDevice> devices(count);
  if (vkEnumeratePhysicalDevices(instance, &count, devices.data()) != VK_SUCCESS) return {};
  devices.resize(count);
  return devices;
}

std::vector<std::string> describe_devices(const std::vector<VkPhysicalDevice>& devices) {
  std::vector<std::string> out;
  for (size_t i = 0; i < devices.size(); ++i) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devices[i], &p);
    out.push_back(std::to_string(i) + ": " + p.deviceName + " [" + type_name(p.deviceType) + "]");
  }
  return out;
}

std::string join(const std::vector<std::string>& parts, const char* sep) {
  std::string s;
  for (size_t i = 0; i < parts.size(); ++i) s.append(i ? sep : "").append(parts[i]);
  return s;
}

// The device index for `selector` (index or case-insensitive name substring; empty: discrete,
// integrated, then anything) among devices with a universal queue, or -1 with reason.
int choose_device(const std::vector<VkPhysicalDevice>& devices, const std::string& selector,
                  std::string* reason) {
  if (devices.empty()) {
    *reason = "the Vulkan loader found no physical device";
    return -1;
  }
  if (!selector.empty()) {
    const bool numeric = std::all_of(selector.begin(), selector.end(),
                                     [](unsigned char c) { return std::isdigit(c); });
    int found = -1;
    if (numeric) {
      const unsigned long index = std::strtoul(selector.c_str(), nullptr, 10);
      if (index < devices.size()) found = static_cast<int>(index);
    } else {
      for (size_t i = 0; i < devices.size() && found < 0; ++i) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(devices[i], &p);
        if (lower(p.deviceName).find(lower(selector)) != std::string::npos)
          found = static_cast<int>(i);
      }
    }
    if (found < 0) {
      *reason =
          std::string("AOEVAL_VK_DEVICE=")
              .append(selector)
              .append(" matches no device; devices: " + join(describe_devices(devices), ", "));
      return -1;
    }
    if (universal_queue_family(devices[found]) < 0) {
      *reason = std::string("device ")
                    .append(describe_devices(devices)[found])
                    .append(" has no queue with both graphics and compute");
      return -1;
    }
    return found;
  }
  for (VkPhysicalDeviceType wanted :
       {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU}) {
    for (size_t i = 0; i < devices.size(); ++i) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(devices[i], &p);
      if (p.deviceType == wanted && universal_queue_family(devices[i]) >= 0)
        return static_cast<int>(i);
    }
  }
  for (size_t i = 0; i < devices.size(); ++i)
    if (universal_queue_family(devices[i]) >= 0) return static_cast<int>(i);
  *reason = "no device has a queue with both graphics and compute; devices: " +
            join(describe_devices(devices), ", ");
  return -1;
}

}  // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL Context::on_debug_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    auto* self = static_cast<Context*>(user);
    std::lock_guard lock(self->messages_mutex_);
    self->validation_errors_.emplace_back(data && data->pMessage ? data->pMessage : "(no message)");
  }
  return VK_FALSE;
}

std::unique_ptr<Context> Context::create(const ContextOptions& options, std::string* reason) {
  std::string why;
  const bool want_validation = options.validation.value_or(
#ifdef NDEBUG
      env_flag("AOEVAL_VK_VALIDATION")
#else
      true
#endif
  );
  const bool validation = want_validation && validation_layer_present();
  const bool debug_utils = validation && debug_utils_present();

  std::unique_ptr<Context> c(new Context());
  c->instance_ = make_instance(validation, debug_utils, &why);
  if (c->instance_ == VK_NULL_HANDLE) {
    if (reason) *reason = why;
    return nullptr;
  }
  c->validation_ = validation;
  if (debug_utils) {
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(c->instance_, "vkCreateDebugUtilsMessengerEXT"));
    auto info = make_info<VkDebugUtilsMessengerCreateInfoEXT>(
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    info.pfnUserCallback = &Context::on_debug_message;
    info.pUserData = c.get();
    if (create_messenger) create_messenger(c->instance_, &info, nullptr, &c->messenger_);
  }

  std::string selector = options.device;
  if (selector.empty())
    if (const char* env = std::getenv("AOEVAL_VK_DEVICE")) selector = env;
  const auto devices = physical_devices(c->instance_);
  const int index = choose_device(devices, selector, &why);
  if (index < 0) {
    if (reason) *reason = why;
    return nullptr;
  }
  c->physical_ = devices[index];
  vkGetPhysicalDeviceProperties(c->physical_, &c->properties_);
  vkGetPhysicalDeviceMemoryProperties(c->physical_, &c->memory_);
  c->device_name_ = c->properties_.deviceName;
  c->queue_family_ = static_cast<uint32_t>(universal_queue_family(c->physical_));
  {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(c->physical_, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(c->physical_, &count, families.data());
    c->timestamp_valid_bits_ = families[c->queue_family_].timestampValidBits;
  }
  {
    auto driver = make_info<VkPhysicalDeviceDriverProperties>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
    auto p2 =
        make_info<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
    if (c->properties_.apiVersion >= VK_API_VERSION_1_2) {
      p2.pNext = &driver;
      vkGetPhysicalDeviceProperties2(c->physical_, &p2);
      c->driver_info_ = driver.driverInfo;
    }
  }

  const float priority = 1.0f;
  auto queue = make_info<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue.queueFamilyIndex = c->queue_family_;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  auto device = make_info<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  device.queueCreateInfoCount = 1;
  device.pQueueCreateInfos = &queue;
  VkResult r = vkCreateDevice(c->physical_, &device, nullptr, &c->device_);
  if (r != VK_SUCCESS) {
    if (reason) *reason = std::string("vkCreateDevice failed: ") + result_name(r);
    return nullptr;
  }
  vkGetDeviceQueue(c->device_, c->queue_family_, 0, &c->queue_);
  auto pool = make_info<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = c->queue_family_;
  r = vkCreateCommandPool(c->device_, &pool, nullptr, &c->pool_);
  if (r != VK_SUCCESS) {
    if (reason) *reason = std::string("vkCreateCommandPool failed: ") + result_name(r);
    return nullptr;
  }
  return c;
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    kept_.clear();
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

std::shared_ptr<void> Context::kept(const std::string& key,
                                    const std::function<std::shared_ptr<void>()>& make) {
  std::lock_guard<std::mutex> lock(kept_mutex_);
  std::shared_ptr<void>& object = kept_[key];
  if (!object) object = make();
  return object;
}

std::string Context::device_description() const {
  std::string s = device_name_ + " [" + type_name(properties_.deviceType);
  if (!driver_info_.empty()) s += ", " + driver_info_;
  return s + "]";
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags properties) const {
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) &&
        (memory_.memoryTypes[i].propertyFlags & properties) == properties)
      return i;
  throw VulkanError("no Vulkan memory type with the requested properties on " + device_name_);
}

void Context::submit(const std::function<void(VkCommandBuffer)>& record) {
  std::lock_guard lock(submit_mutex_);
  auto alloc =
      make_info<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device_, &alloc, &cmd), "vkAllocateCommandBuffers");
  VkFence fence = VK_NULL_HANDLE;
  struct Cleanup {
    Context* c;
    VkCommandBuffer& cmd;
    VkFence& fence;
    ~Cleanup() {
      if (fence) vkDestroyFence(c->device_, fence, nullptr);
      vkFreeCommandBuffers(c->device_, c->pool_, 1, &cmd);
    }
  } cleanup{this, cmd, fence};

  auto begin = make_info<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  record(cmd);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  auto fence_info = make_info<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  check(vkCreateFence(device_, &fence_info, nullptr, &fence), "vkCreateFence");
  auto submit = make_info<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  check(vkQueueSubmit(queue_, 1, &submit, fence), "vkQueueSubmit");
  check(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  throw_if_validation_errors();
}

std::vector<std::string> Context::validation_errors() const {
  std::lock_guard lock(messages_mutex_);
  return validation_errors_;
}

void Context::throw_if_validation_errors() {
  std::vector<std::string> errors;
  {
    std::lock_guard lock(messages_mutex_);
    errors.swap(validation_errors_);
  }
  if (errors.empty()) return;
  throw VulkanError("Vulkan validation: " + join(errors, "\n"));
}

std::vector<std::string> list_devices(std::string* reason) {
  VkInstance instance = make_instance(false, false, reason);
  if (instance == VK_NULL_HANDLE) return {};
  auto names = describe_devices(physical_devices(instance));
  vkDestroyInstance(instance, nullptr);
  if (names.empty() && reason) *reason = "the Vulkan loader found no physical device";
  return names;
}

Context* shared_context(std::string* reason) {
  static std::once_flag once;
  static std::unique_ptr<Context> context;
  static std::string why;
  std::call_once(once, [] { context = Context::create({}, &why); });
  if (!context && reason) *reason = why;
  return context.get();
}

Context& require_shared_context() {
  std::string reason;
  Context* c = shared_context(&reason);
  if (!c) throw EstimatorUnavailable("no Vulkan device (" + reason + ")");
  return *c;
}

}  // namespace aoeval::vk
