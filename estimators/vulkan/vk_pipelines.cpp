#include "estimators/vulkan/vk_pipelines.h"

#include <cstdint>
#include <map>
#include <memory>
#include <sstream>

namespace aoeval::vk {

namespace {

VkShaderModule make_module(VkDevice device, const SpirvCode& code, const std::string& name) {
  if (!code.words || code.bytes == 0) throw VulkanError(name + ": no SPIR-V code");
  auto info = make_info<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  info.codeSize = code.bytes;
  info.pCode = code.words;
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device, &info, nullptr, &module),
        (name + ": vkCreateShaderModule").c_str());
  return module;
}

// Specialisation info pointing into `entries`/`data`, which must outlive its use.
VkSpecializationInfo spec_info(const std::vector<SpecConstant>& constants,
                               std::vector<VkSpecializationMapEntry>& entries,
                               std::vector<uint32_t>& data) {
  entries.clear();
  data.clear();
  for (const SpecConstant& c : constants) {
    entries.push_back({c.id, static_cast<uint32_t>(data.size() * 4), 4});
    data.push_back(c.bits);
  }
  VkSpecializationInfo info{};
  info.mapEntryCount = static_cast<uint32_t>(entries.size());
  info.pMapEntries = entries.data();
  info.dataSize = data.size() * 4;
  info.pData = data.data();
  return info;
}

struct ModuleGuard {
  VkDevice device;
  VkShaderModule module;
  ~ModuleGuard() {
    if (module) vkDestroyShaderModule(device, module, nullptr);
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// PipelineBase

namespace {

// The sampler (when a binding is a combined image sampler), set layout and pipeline layout of
// `bindings` and one push-constant range; nothing is left created when it throws.
void make_layouts(VkDevice device, const std::vector<VkDescriptorType>& bindings,
                  uint32_t push_constant_bytes, const std::string& name, VkSampler& sampler,
                  VkDescriptorSetLayout& set_layout, VkPipelineLayout& layout) {
  std::vector<VkDescriptorSetLayoutBinding> entries;
  bool needs_sampler = false;
  for (size_t i = 0; i < bindings.size(); ++i) {
    VkDescriptorSetLayoutBinding b{};
    b.binding = static_cast<uint32_t>(i);
    b.descriptorType = bindings[i];
    b.descriptorCount = 1;
    b.stageFlags = VK_SHADER_STAGE_ALL;
    entries.push_back(b);
    needs_sampler |= bindings[i] == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  }
  try {
    if (needs_sampler) {
      auto s = make_info<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
      s.magFilter = s.minFilter = VK_FILTER_LINEAR;
      s.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
      s.addressModeU = s.addressModeV = s.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
      check(vkCreateSampler(device, &s, nullptr, &sampler), "vkCreateSampler");
    }
    auto set = make_info<VkDescriptorSetLayoutCreateInfo>(
        VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    set.bindingCount = static_cast<uint32_t>(entries.size());
    set.pBindings = entries.data();
    check(vkCreateDescriptorSetLayout(device, &set, nullptr, &set_layout),
          (name + ": vkCreateDescriptorSetLayout").c_str());
    VkPushConstantRange range{VK_SHADER_STAGE_ALL, 0, push_constant_bytes};
    auto info =
        make_info<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    info.setLayoutCount = 1;
    info.pSetLayouts = &set_layout;
    info.pushConstantRangeCount = push_constant_bytes > 0 ? 1 : 0;
    info.pPushConstantRanges = &range;
    check(vkCreatePipelineLayout(device, &info, nullptr, &layout),
          (name + ": vkCreatePipelineLayout").c_str());
  } catch (...) {
    if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
    if (sampler) vkDestroySampler(device, sampler, nullptr);
    set_layout = VK_NULL_HANDLE;
    sampler = VK_NULL_HANDLE;
    throw;
  }
}

// A compute pipeline's handles as the context keeps them (ComputePipeline's shared_).
struct CompiledCompute {
  VkDevice device = VK_NULL_HANDLE;
  VkSampler sampler = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  CompiledCompute() = default;
  CompiledCompute(const CompiledCompute&) = delete;
  CompiledCompute& operator=(const CompiledCompute&) = delete;
  // Lends its handles to a pipeline's members (PipelineBase's, which then do not destroy them).
  void lend(VkSampler& s, VkDescriptorSetLayout& sl, VkPipelineLayout& l, VkPipeline& p) const {
    s = sampler;
    sl = set_layout;
    l = layout;
    p = pipeline;
  }
  ~CompiledCompute() {
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
    if (sampler) vkDestroySampler(device, sampler, nullptr);
  }
};

// A compiled pipeline's start: its device, sampler and layouts.
template <class Compiled>
std::shared_ptr<Compiled> with_layouts(VkDevice device,
                                       const std::vector<VkDescriptorType>& bindings,
                                       uint32_t push_constant_bytes, const std::string& name) {
  auto compiled = std::make_shared<Compiled>();
  compiled->device = device;
  make_layouts(device, bindings, push_constant_bytes, name, compiled->sampler, compiled->set_layout,
               compiled->layout);
  return compiled;
}

// The SPIR-V words themselves, not their address: a plug-in's code lives in a vector that a later
// plug-in's may reuse.
void put_code(std::ostringstream& key, const SpirvCode& code) {
  key << code.bytes << ':';
  if (code.words)
    key.write(reinterpret_cast<const char*>(code.words), static_cast<std::streamsize>(code.bytes));
}

// What makes two compute pipelines the same: the code, the bindings, the push-constant size and
// the specialisation constants.
std::string compute_key(const SpirvCode& code, const std::vector<VkDescriptorType>& bindings,
                        uint32_t push_constant_bytes, const std::vector<SpecConstant>& spec) {
  std::ostringstream key;
  key << "compute ";
  put_code(key, code);
  key << " push " << push_constant_bytes << " bindings";
  for (VkDescriptorType t : bindings) key << ' ' << static_cast<int>(t);
  key << " spec";
  for (const SpecConstant& c : spec) key << ' ' << c.id << '=' << c.bits;
  return key.str();
}

}  // namespace

PipelineBase::PipelineBase(Context& context, const std::vector<VkDescriptorType>& bindings,
                           uint32_t push_constant_bytes, const std::string& name, bool own_layouts)
    : context_(context), name_(name), bindings_(bindings), push_bytes_(push_constant_bytes) {
  if (own_layouts)
    make_layouts(context.device(), bindings, push_constant_bytes, name, sampler_, set_layout_,
                 layout_);
}

PipelineBase::~PipelineBase() {
  VkDevice device = context_.device();
  for (VkDescriptorPool pool : pools_) vkDestroyDescriptorPool(device, pool, nullptr);
  if (shared_) return;
  if (pipeline_) vkDestroyPipeline(device, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
  if (sampler_) vkDestroySampler(device, sampler_, nullptr);
}

VkDescriptorSet PipelineBase::make_set(const std::vector<Resource>& resources) {
  if (resources.size() != bindings_.size())
    throw VulkanError(name_ + ": make_set got " + std::to_string(resources.size()) +
                      " resources for " + std::to_string(bindings_.size()) + " bindings");
  VkDevice device = context_.device();
  std::map<VkDescriptorType, uint32_t> counts;
  for (VkDescriptorType t : bindings_) ++counts[t];
  std::vector<VkDescriptorPoolSize> sizes;
  for (const auto& [type, count] : counts) sizes.push_back({type, count});
  auto pool_info =
      make_info<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = static_cast<uint32_t>(sizes.size());
  pool_info.pPoolSizes = sizes.data();
  VkDescriptorPool pool = VK_NULL_HANDLE;
  check(vkCreateDescriptorPool(device, &pool_info, nullptr, &pool),
        (name_ + ": vkCreateDescriptorPool").c_str());
  pools_.push_back(pool);
  auto alloc =
      make_info<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &set_layout_;
  VkDescriptorSet set = VK_NULL_HANDLE;
  check(vkAllocateDescriptorSets(device, &alloc, &set),
        (name_ + ": vkAllocateDescriptorSets").c_str());

  std::vector<VkDescriptorImageInfo> images(resources.size());
  std::vector<VkDescriptorBufferInfo> buffers(resources.size());
  std::vector<VkWriteDescriptorSet> writes;
  for (size_t i = 0; i < resources.size(); ++i) {
    auto w = make_info<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstSet = set;
    w.dstBinding = static_cast<uint32_t>(i);
    w.descriptorCount = 1;
    w.descriptorType = bindings_[i];
    const bool wants_image = bindings_[i] == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE ||
                             bindings_[i] == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    if (wants_image != (resources[i].image != nullptr))
      throw VulkanError(name_ + ": binding " + std::to_string(i) + " expects " +
                        (wants_image ? "an image" : "a buffer"));
    if (wants_image) {
      images[i] = {sampler_, resources[i].image->view(), resources[i].image->layout()};
      w.pImageInfo = &images[i];
    } else {
      buffers[i] = {resources[i].buffer->handle(), 0, VK_WHOLE_SIZE};
      w.pBufferInfo = &buffers[i];
    }
    writes.push_back(w);
  }
  vkUpdateDescriptorSets(device, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
  return set;
}

void PipelineBase::push(VkCommandBuffer cmd, const void* data, size_t bytes) const {
  if (bytes > push_bytes_)
    throw VulkanError(name_ + ": " + std::to_string(bytes) + " push-constant bytes, " +
                      std::to_string(push_bytes_) + " declared");
  if (bytes > 0)
    vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_ALL, 0, static_cast<uint32_t>(bytes), data);
}

// ---------------------------------------------------------------------------------------------
// ComputePipeline

ComputePipeline::ComputePipeline(Context& context, const std::string& name, SpirvCode spirv,
                                 const std::vector<VkDescriptorType>& bindings,
                                 uint32_t push_constant_bytes,
                                 const std::vector<SpecConstant>& spec_constants)
    : PipelineBase(context, bindings, push_constant_bytes, name, false) {
  shared_ = context.kept(compute_key(spirv, bindings, push_constant_bytes, spec_constants), [&] {
    VkDevice device = context.device();
    auto compiled = with_layouts<CompiledCompute>(device, bindings, push_constant_bytes, name_);
    ModuleGuard module{device, make_module(device, spirv, name_)};
    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint32_t> data;
    const VkSpecializationInfo spec = spec_info(spec_constants, entries, data);
    auto info =
        make_info<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    info.stage = make_info<VkPipelineShaderStageCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module.module;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = &spec;
    info.layout = compiled->layout;
    check(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &compiled->pipeline),
          (name_ + ": vkCreateComputePipelines").c_str());
    context.throw_if_validation_errors();
    return std::shared_ptr<void>(std::move(compiled));
  });
  static_cast<const CompiledCompute*>(shared_.get())
      ->lend(sampler_, set_layout_, layout_, pipeline_);
}

void ComputePipeline::dispatch(VkCommandBuffer cmd, VkDescriptorSet set, const void* push_data,
                               size_t push_bytes, uint32_t groups_x, uint32_t groups_y,
                               uint32_t groups_z) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set, 0, nullptr);
  push(cmd, push_data, push_bytes);
  vkCmdDispatch(cmd, groups_x, groups_y, groups_z);
}

// ---------------------------------------------------------------------------------------------
// GraphicsPipeline

namespace {

// The render pass of `desc`: colour attachments stay in GENERAL (the layer's one layout), cleared
// and stored; depth is cleared and discarded.
VkRenderPass make_render_pass(VkDevice device, const GraphicsDesc& desc, const std::string& name) {
  std::vector<VkAttachmentDescription> attachments;
  std::vector<VkAttachmentReference> color_refs;
  for (VkFormat f : desc.color_formats) {
    VkAttachmentDescription a{};
    a.format = f;
    a.samples = VK_SAMPLE_COUNT_1_BIT;
    a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.initialLayout = VK_IMAGE_LAYOUT_GENERAL;
    a.finalLayout = VK_IMAGE_LAYOUT_GENERAL;
    color_refs.push_back({static_cast<uint32_t>(attachments.size()), VK_IMAGE_LAYOUT_GENERAL});
    attachments.push_back(a);
  }
  VkAttachmentDescription depth{};
  depth.format = desc.depth_format;
  depth.samples = VK_SAMPLE_COUNT_1_BIT;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  depth.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.initialLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  depth.finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  const VkAttachmentReference depth_ref{static_cast<uint32_t>(attachments.size()),
                                        VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  attachments.push_back(depth);
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = static_cast<uint32_t>(color_refs.size());
  subpass.pColorAttachments = color_refs.data();
  subpass.pDepthStencilAttachment = &depth_ref;
  auto rp = make_info<VkRenderPassCreateInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO);
  rp.attachmentCount = static_cast<uint32_t>(attachments.size());
  rp.pAttachments = attachments.data();
  rp.subpassCount = 1;
  rp.pSubpasses = &subpass;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  check(vkCreateRenderPass(device, &rp, nullptr, &render_pass),
        (name + ": vkCreateRenderPass").c_str());
  return render_pass;
}

VkPipeline make_graphics_pipeline(VkDevice device, const GraphicsDesc& desc,
                                  const std::string& name, VkPipelineLayout layout,
                                  VkRenderPass render_pass) {
  ModuleGuard vertex{device, make_module(device, desc.vertex, name + " (vertex)")};
  ModuleGuard fragment{device, make_module(device, desc.fragment, name + " (fragment)")};
  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> data;
  const VkSpecializationInfo spec = spec_info(desc.spec_constants, entries, data);
  VkPipelineShaderStageCreateInfo stages[2];
  for (auto& stage : stages)
    stage = make_info<VkPipelineShaderStageCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vertex.module;
  stages[0].pName = "main";
  stages[0].pSpecializationInfo = &spec;
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = fragment.module;
  stages[1].pName = "main";
  stages[1].pSpecializationInfo = &spec;

  auto vertex_input = make_info<VkPipelineVertexInputStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
  auto assembly = make_info<VkPipelineInputAssemblyStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  auto viewport = make_info<VkPipelineViewportStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  auto raster = make_info<VkPipelineRasterizationStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = VK_CULL_MODE_NONE;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  auto multisample = make_info<VkPipelineMultisampleStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  auto depth_state = make_info<VkPipelineDepthStencilStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
  depth_state.depthTestEnable = VK_TRUE;
  depth_state.depthWriteEnable = VK_TRUE;
  depth_state.depthCompareOp = desc.depth_compare;
  std::vector<VkPipelineColorBlendAttachmentState> blends(desc.color_formats.size());
  for (auto& b : blends)
    b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                       VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  auto blend = make_info<VkPipelineColorBlendStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
  blend.attachmentCount = static_cast<uint32_t>(blends.size());
  blend.pAttachments = blends.data();
  const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  auto dynamic = make_info<VkPipelineDynamicStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;

  auto info =
      make_info<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
  info.stageCount = 2;
  info.pStages = stages;
  info.pVertexInputState = &vertex_input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth_state;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = layout;
  info.renderPass = render_pass;
  info.subpass = 0;
  VkPipeline pipeline = VK_NULL_HANDLE;
  check(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
        (name + ": vkCreateGraphicsPipelines").c_str());
  return pipeline;
}

// A graphics pipeline's handles as the context keeps them (GraphicsPipeline's shared_).
struct CompiledGraphics : CompiledCompute {
  VkRenderPass render_pass = VK_NULL_HANDLE;
  ~CompiledGraphics() {
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    pipeline = VK_NULL_HANDLE;
    if (render_pass) vkDestroyRenderPass(device, render_pass, nullptr);
  }
};

std::string graphics_key(const GraphicsDesc& d) {
  std::ostringstream key;
  key << "graphics " << compute_key(d.vertex, d.bindings, d.push_constant_bytes, d.spec_constants)
      << " fragment ";
  put_code(key, d.fragment);
  key << " depth " << static_cast<int>(d.depth_format) << ' ' << static_cast<int>(d.depth_compare)
      << " colours";
  for (VkFormat f : d.color_formats) key << ' ' << static_cast<int>(f);
  return key.str();
}

}  // namespace

GraphicsPipeline::GraphicsPipeline(Context& context, const GraphicsDesc& desc)
    : PipelineBase(context, desc.bindings, desc.push_constant_bytes, desc.name, false) {
  // Compiled once per context, as ComputePipeline's are.
  shared_ = context.kept(graphics_key(desc), [&] {
    VkDevice device = context.device();
    auto compiled =
        with_layouts<CompiledGraphics>(device, desc.bindings, desc.push_constant_bytes, name_);
    compiled->render_pass = make_render_pass(device, desc, name_);
    compiled->pipeline =
        make_graphics_pipeline(device, desc, name_, compiled->layout, compiled->render_pass);
    context.throw_if_validation_errors();
    return std::shared_ptr<void>(std::move(compiled));
  });
  const auto& compiled = *static_cast<const CompiledGraphics*>(shared_.get());
  compiled.lend(sampler_, set_layout_, layout_, pipeline_);
  render_pass_ = compiled.render_pass;
}

GraphicsPipeline::~GraphicsPipeline() = default;

// ---------------------------------------------------------------------------------------------
// Framebuffer

Framebuffer::Framebuffer(Context& context, const GraphicsPipeline& pipeline,
                         const std::vector<const Image2D*>& colors, const Image2D& depth)
    : context_(context),
      width_(static_cast<uint32_t>(depth.width())),
      height_(static_cast<uint32_t>(depth.height())) {
  std::vector<VkImageView> views;
  for (const Image2D* c : colors) {
    if (c->width() != depth.width() || c->height() != depth.height())
      throw VulkanError("vk::Framebuffer: attachments of different sizes");
    views.push_back(c->view());
  }
  views.push_back(depth.view());
  auto info = make_info<VkFramebufferCreateInfo>(VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO);
  info.renderPass = pipeline.render_pass();
  info.attachmentCount = static_cast<uint32_t>(views.size());
  info.pAttachments = views.data();
  info.width = width_;
  info.height = height_;
  info.layers = 1;
  check(vkCreateFramebuffer(context.device(), &info, nullptr, &framebuffer_),
        "vkCreateFramebuffer");
}

Framebuffer::~Framebuffer() {
  if (framebuffer_) vkDestroyFramebuffer(context_.device(), framebuffer_, nullptr);
}

void Framebuffer::begin(VkCommandBuffer cmd, const GraphicsPipeline& pipeline,
                        const std::vector<VkClearColorValue>& color_clears,
                        float depth_clear) const {
  std::vector<VkClearValue> clears;
  for (const VkClearColorValue& c : color_clears) {
    VkClearValue v{};
    v.color = c;
    clears.push_back(v);
  }
  VkClearValue d{};
  d.depthStencil = {depth_clear, 0};
  clears.push_back(d);
  auto info = make_info<VkRenderPassBeginInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO);
  info.renderPass = pipeline.render_pass();
  info.framebuffer = framebuffer_;
  info.renderArea = {{0, 0}, {width_, height_}};
  info.clearValueCount = static_cast<uint32_t>(clears.size());
  info.pClearValues = clears.data();
  vkCmdBeginRenderPass(cmd, &info, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  const VkViewport viewport{0.0f, 0.0f, static_cast<float>(width_), static_cast<float>(height_),
                            0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, {width_, height_}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

void Framebuffer::end(VkCommandBuffer cmd) const {
  vkCmdEndRenderPass(cmd);
}

}  // namespace aoeval::vk
