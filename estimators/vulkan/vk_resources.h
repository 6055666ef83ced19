// Device buffers and 2D images, RAII, with upload/download through host-visible staging buffers.
//
// Layout convention: every Image2D lives in VK_IMAGE_LAYOUT_GENERAL from construction on (colour
// and storage images alike; depth images in DEPTH_STENCIL_ATTACHMENT_OPTIMAL). Shaders, copies and
// render passes all use it there, so callers never transition layouts; they only put barriers
// between passes (vk_commands.h).
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <vector>

#include "estimators/vulkan/vk_context.h"

namespace aoeval::vk {

// A VkBuffer with its own memory. Device-local unless `host_visible` (then also mappable).
class Buffer {
 public:
  Buffer() = default;
  // `usage` gets TRANSFER_SRC and TRANSFER_DST added (for staging).
  Buffer(Context& context, VkDeviceSize bytes, VkBufferUsageFlags usage, bool host_visible = false);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  bool valid() const { return buffer_ != VK_NULL_HANDLE; }

  // Copies `bytes` (<= size()) to/from the start of the buffer; submits and waits.
  void upload(const void* data, size_t bytes);
  void download(void* data, size_t bytes) const;
  template <class T>
  void upload(const std::vector<T>& values) {
    upload(values.data(), values.size() * sizeof(T));
  }
  template <class T>
  std::vector<T> download() const {
    std::vector<T> values(static_cast<size_t>(size_ / sizeof(T)));
    download(values.data(), values.size() * sizeof(T));
    return values;
  }
  // Host pointer of a host-visible buffer (coherent memory); nullptr otherwise.
  void* mapped() const { return mapped_; }

 private:
  void release();
  Context* context_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

// A storage buffer holding `values` (uploaded at once: submits and waits).
template <class T>
Buffer storage_buffer(Context& context, const std::vector<T>& values) {
  Buffer buffer(context, values.size() * sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  buffer.upload(values);
  return buffer;
}

// Bytes per texel of the formats aoeval uses (R32F, R32UI, R32I, RG32F, RGBA32F, RGBA8, RGBA16F,
// D32); throws VulkanError for others.
size_t texel_bytes(VkFormat format);
bool is_depth_format(VkFormat format);

// A 2D image with one mip level and a view. Colour formats get STORAGE | TRANSFER_SRC |
// TRANSFER_DST | SAMPLED usage plus `extra_usage` (e.g. COLOR_ATTACHMENT) and start in GENERAL,
// cleared to zero; depth formats get DEPTH_STENCIL_ATTACHMENT | `extra_usage`.
class Image2D {
 public:
  Image2D() = default;
  Image2D(Context& context, int width, int height, VkFormat format,
          VkImageUsageFlags extra_usage = 0);
  ~Image2D();
  Image2D(Image2D&& other) noexcept;
  Image2D& operator=(Image2D&& other) noexcept;
  Image2D(const Image2D&) = delete;
  Image2D& operator=(const Image2D&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  VkFormat format() const { return format_; }
  VkImageLayout layout() const { return layout_; }
  int width() const { return width_; }
  int height() const { return height_; }
  size_t byte_size() const { return static_cast<size_t>(width_) * height_ * texel_bytes(format_); }
  bool valid() const { return image_ != VK_NULL_HANDLE; }

  // Row-major, row 0 at the top, tightly packed texels (byte_size() bytes); colour formats only.
  // Each submits and waits.
  void upload(const void* data, size_t bytes);
  void download(void* data, size_t bytes) const;
  template <class T>
  void upload(const std::vector<T>& texels) {
    upload(texels.data(), texels.size() * sizeof(T));
  }
  // T is the texel component type (float for R32F/RGBA32F, uint32_t for R32UI): returns
  // width * height * components values.
  template <class T>
  std::vector<T> download() const {
    std::vector<T> values(byte_size() / sizeof(T));
    download(values.data(), values.size() * sizeof(T));
    return values;
  }
  // Records a copy of the image into `buffer` (tightly packed) / from it; no barrier included.
  void record_copy_to(VkCommandBuffer cmd, const Buffer& buffer) const;
  void record_copy_from(VkCommandBuffer cmd, const Buffer& buffer);

 private:
  void release();
  Context* context_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkImageLayout layout_ = VK_IMAGE_LAYOUT_UNDEFINED;
  int width_ = 0, height_ = 0;
};

}  // namespace aoeval::vk
