#include "estimators/vulkan/vk_resources.h"

#include <cstring>
#include <utility>

namespace aoeval::vk {

// ---------------------------------------------------------------------------------------------
// Buffer

Buffer::Buffer(Context& context, VkDeviceSize bytes, VkBufferUsageFlags usage, bool host_visible)
    : context_(&context), size_(bytes) {
  if (bytes == 0) throw VulkanError("vk::Buffer: zero-sized buffer");
  VkDevice device = context.device();
  auto info = make_info<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = bytes;
  info.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(device, &info, nullptr, &buffer_), "vkCreateBuffer");
  try {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, buffer_, &req);
    auto alloc = make_info<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = context.memory_type(
        req.memoryTypeBits,
        host_visible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                     : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkAllocateMemory(device, &alloc, nullptr, &memory_), "vkAllocateMemory (buffer)");
    check(vkBindBufferMemory(device, buffer_, memory_, 0), "vkBindBufferMemory");
    if (host_visible)
      check(vkMapMemory(device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  } catch (...) {
    release();
    throw;
  }
}

Buffer::~Buffer() {
  release();
}

void Buffer::release() {
  if (!context_) return;
  VkDevice device = context_->device();
  if (mapped_) vkUnmapMemory(device, memory_);
  if (buffer_) vkDestroyBuffer(device, buffer_, nullptr);
  if (memory_) vkFreeMemory(device, memory_, nullptr);
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
}

Buffer::Buffer(Buffer&& o) noexcept
    : context_(std::exchange(o.context_, nullptr)),
      buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)),
      size_(std::exchange(o.size_, 0)),
      mapped_(std::exchange(o.mapped_, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    context_ = std::exchange(o.context_, nullptr);
    buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(o.size_, 0);
    mapped_ = std::exchange(o.mapped_, nullptr);
  }
  return *this;
}

void Buffer::upload(const void* data, size_t bytes) {
  if (bytes > size_) throw VulkanError("vk::Buffer::upload: more bytes than the buffer holds");
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(mapped_, data, bytes);
    return;
  }
  Buffer staging(*context_, bytes, 0, true);
  std::memcpy(staging.mapped(), data, bytes);
  context_->submit([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(cmd, staging.handle(), buffer_, 1, &region);
  });
}

void Buffer::download(void* data, size_t bytes) const {
  if (bytes > size_) throw VulkanError("vk::Buffer::download: more bytes than the buffer holds");
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(data, mapped_, bytes);
    return;
  }
  Buffer staging(*context_, bytes, 0, true);
  context_->submit([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer_, staging.handle(), 1, &region);
    // Make the transfer write visible to the host read after the fence.
    auto barrier = make_info<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &barrier, 0, nullptr, 0, nullptr);
  });
  std::memcpy(data, staging.mapped(), bytes);
}

// ---------------------------------------------------------------------------------------------
// Image2D

size_t texel_bytes(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32_SINT:
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_D32_SFLOAT:
      return 4;
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R16G16B16A16_SFLOAT:
      return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
      return 16;
    default:
      throw VulkanError("vk::Image2D: unsupported format " + std::to_string(format));
  }
}

bool is_depth_format(VkFormat format) {
  return format == VK_FORMAT_D32_SFLOAT;
}

namespace {

VkImageAspectFlags aspect_of(VkFormat format) {
  return is_depth_format(format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

VkBufferImageCopy full_copy(int width, int height) {
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {static_cast<uint32_t>(width), static_cast<uint32_t>(height), 1};
  return region;
}

}  // namespace

Image2D::Image2D(Context& context, int width, int height, VkFormat format,
                 VkImageUsageFlags extra_usage)
    : context_(&context), format_(format), width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw VulkanError("vk::Image2D: empty image");
  texel_bytes(format);  // rejects unknown formats
  const bool depth = is_depth_format(format);
  VkDevice device = context.device();
  auto info = make_info<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {static_cast<uint32_t>(width), static_cast<uint32_t>(height), 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage =
      extra_usage | (depth ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                           : VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(device, &info, nullptr, &image_), "vkCreateImage");
  try {
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device, image_, &req);
    auto alloc = make_info<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex =
        context.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkAllocateMemory(device, &alloc, nullptr, &memory_), "vkAllocateMemory (image)");
    check(vkBindImageMemory(device, image_, memory_, 0), "vkBindImageMemory");
    auto view = make_info<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
    view.image = image_;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect_of(format), 0, 1, 0, 1};
    check(vkCreateImageView(device, &view, nullptr, &view_), "vkCreateImageView");

    // Into the one layout it keeps for life (see the header); colour images start at zero.
    layout_ = depth ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL;
    context.submit([&](VkCommandBuffer cmd) {
      auto b = make_info<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
      b.srcAccessMask = 0;
      b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
      b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
      b.newLayout = layout_;
      b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      b.image = image_;
      b.subresourceRange = {aspect_of(format), 0, 1, 0, 1};
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                           VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0, nullptr, 1, &b);
      if (!depth) {
        const VkClearColorValue zero{};
        const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd, image_, layout_, &zero, 1, &range);
        auto m = make_info<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
        m.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        m.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &m, 0, nullptr, 0, nullptr);
      }
    });
  } catch (...) {
    release();
    throw;
  }
}

Image2D::~Image2D() {
  release();
}

void Image2D::release() {
  if (!context_) return;
  VkDevice device = context_->device();
  if (view_) vkDestroyImageView(device, view_, nullptr);
  if (image_) vkDestroyImage(device, image_, nullptr);
  if (memory_) vkFreeMemory(device, memory_, nullptr);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

Image2D::Image2D(Image2D&& o) noexcept
    : context_(std::exchange(o.context_, nullptr)),
      image_(std::exchange(o.image_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)),
      view_(std::exchange(o.view_, VK_NULL_HANDLE)),
      format_(o.format_),
      layout_(o.layout_),
      width_(o.width_),
      height_(o.height_) {}

Image2D& Image2D::operator=(Image2D&& o) noexcept {
  if (this != &o) {
    release();
    context_ = std::exchange(o.context_, nullptr);
    image_ = std::exchange(o.image_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    view_ = std::exchange(o.view_, VK_NULL_HANDLE);
    format_ = o.format_;
    layout_ = o.layout_;
    width_ = o.width_;
    height_ = o.height_;
  }
  return *this;
}

void Image2D::record_copy_to(VkCommandBuffer cmd, const Buffer& buffer) const {
  const VkBufferImageCopy region = full_copy(width_, height_);
  vkCmdCopyImageToBuffer(cmd, image_, layout_, buffer.handle(), 1, &region);
}

void Image2D::record_copy_from(VkCommandBuffer cmd, const Buffer& buffer) {
  const VkBufferImageCopy region = full_copy(width_, height_);
  vkCmdCopyBufferToImage(cmd, buffer.handle(), image_, layout_, 1, &region);
}

void Image2D::upload(const void* data, size_t bytes) {
  if (is_depth_format(format_)) throw VulkanError("vk::Image2D::upload: depth image");
  if (bytes != byte_size()) throw VulkanError("vk::Image2D::upload: size mismatch");
  Buffer staging(*context_, bytes, 0, true);
  std::memcpy(staging.mapped(), data, bytes);
  context_->submit([&](VkCommandBuffer cmd) {
    // Earlier users of the image are done before the copy overwrites it, and later ones see it.
    auto m = make_info<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    m.srcAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    m.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         1, &m, 0, nullptr, 0, nullptr);
    record_copy_from(cmd, staging);
    m.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    m.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0,
                         1, &m, 0, nullptr, 0, nullptr);
  });
}

void Image2D::download(void* data, size_t bytes) const {
  if (is_depth_format(format_)) throw VulkanError("vk::Image2D::download: depth image");
  if (bytes != byte_size()) throw VulkanError("vk::Image2D::download: size mismatch");
  Buffer staging(*context_, bytes, 0, true);
  context_->submit([&](VkCommandBuffer cmd) {
    auto m = make_info<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    m.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    m.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         1, &m, 0, nullptr, 0, nullptr);
    record_copy_to(cmd, staging);
    m.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    m.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &m,
                         0, nullptr, 0, nullptr);
  });
  std::memcpy(data, staging.mapped(), bytes);
}

}  // namespace aoeval::vk
