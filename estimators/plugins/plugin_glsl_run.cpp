// GLSL plug-ins, running: the passes of a compiled plug-in (plugin_glsl_compile.cpp) on a Vulkan
// context of their own, frame by frame, with the ABI's images and uniform block
// (plugin_glsl_abi.h), a time-out per frame and the checks of the AO they write.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

#include "base/errors.h"
#include "estimators/plugins/plugin_glsl.h"
#include "estimators/plugins/plugin_glsl_abi.h"
#include "estimators/plugins/plugin_process.h"
#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_context.h"
#include "estimators/vulkan/vk_pipelines.h"
#include "estimators/vulkan/vk_resources.h"
#include "scenes/random.h"
#include "scenes/scene.h"

namespace aoeval {

namespace {

// GLSL plug-ins run on a Vulkan context of their own, not the shared one: a shader that overruns
// its timeout_s cannot be stopped (Vulkan has no way to cancel a dispatch, and lavapipe runs it on
// CPU threads to its end), so its context is abandoned with everything made from it, never
// destroyed (destroying a busy device is invalid), and the next frame gets a fresh context, while
// the built-in estimators' shared context is untouched. Abandoned contexts stay reachable here.
struct PluginContexts {
  std::mutex mutex;
  std::unique_ptr<vk::Context> current;
  std::vector<std::unique_ptr<vk::Context>>* abandoned =
      new std::vector<std::unique_ptr<vk::Context>>;
};
PluginContexts& plugin_contexts() {
  static PluginContexts contexts;
  return contexts;
}

vk::Context& plugin_context() {
  PluginContexts& c = plugin_contexts();
  std::lock_guard lock(c.mutex);
  if (!c.current) {
    std::string reason;
    c.current = vk::Context::create({}, &reason);
    if (!c.current) throw EstimatorUnavailable("no Vulkan device (" + reason + ")");
  }
  return *c.current;
}

void abandon_plugin_context(const vk::Context* context) {
  PluginContexts& c = plugin_contexts();
  std::lock_guard lock(c.mutex);
  if (c.current.get() == context) c.abandoned->push_back(std::move(c.current));
}

class GlslEstimator : public Estimator {
 public:
  GlslEstimator(const PluginManifest& m, const ParamSet& params)
      : manifest_(m), params_(params), shaders_(compile_glsl_plugin(m)) {
    for (const PassShader& s : shaders_)
      for (const std::string& risk : lavapipe_loop_risks(s.code.spirv))
        loop_risks_.push_back(s.name + ": " + risk);
    // Integer parameters are the usual loop bounds (samples, steps, taps): their product is what
    // nested loops run ("seed" is a number, never a bound).
    std::string names;
    int64_t product = 1;
    for (const ParamSpec& p : m.params) {
      if (p.type != ParamType::integer || p.name == "seed") continue;
      const int64_t v = params.json().at(p.name).get<int64_t>();
      if (v <= 1) continue;
      names += (names.empty() ? "" : " x ") + p.name;
      product = std::min(product * std::min(v, kLavapipeLoopCap + 1), int64_t{1} << 40);
      if (v > kLavapipeLoopCap)
        loop_risks_.push_back("parameter " + p.name + " = " + std::to_string(v));
    }
    if (loop_risks_.empty() && product > kLavapipeLoopCap && names.find(" x ") != std::string::npos)
      loop_risks_.push_back("parameters " + names + " = " + std::to_string(product));
  }

  // The row's warning when lavapipe's loop cap may have cut this estimate short (see
  // lavapipe_loop_risks); other devices have no such cap.
  nlohmann::json derived() const override {
    nlohmann::json d = nlohmann::json::object();
    if (on_lavapipe_ && !loop_risks_.empty()) {
      std::string list;
      for (const std::string& r : loop_risks_) list += (list.empty() ? "" : "; ") + r;
      d["warning"] = "lavapipe ends loops after " + std::to_string(kLavapipeLoopCap) +
                     " iterations per invocation (all loops together), and this shader may need "
                     "more (" +
                     list + ")";
    }
    return d;
  }

  // Over a sequence one instance runs every frame in order (EstimatorInfo::keeps_state): the
  // device, its pipelines and the last frame's output stay, and each frame uploads its own
  // G-buffer, motion, noise (the seed rule: seed + k) and uniform block.
  void prepare(const EstimateContext& context) override {
    const GBuffer& g = context.gbuffer;
    frame_ = context.frame ? *context.frame : FrameInfo{};  // a still view is frame 0
    still_ = context.frame == nullptr;
    if (!device_ || device_->depth.width() != g.width || device_->depth.height() != g.height)
      make_device(g.width, g.height);
    Device& d = *device_;
    d.upload(g);
    // The noise tile: kGlslNoiseSize^2 texels of four uniform numbers in [0, 1), from the seed.
    SplitMix64 random(mix_seed(static_cast<uint64_t>(seed()), 0x4E4F4953));  // "NOIS"
    std::vector<float> noise(4 * kGlslNoiseSize * kGlslNoiseSize);
    for (float& v : noise) v = random.uniform_float();
    d.noise.upload(noise);
    for (size_t i = 0; i < shaders_.size(); ++i) {
      // One block per pass: they differ only in aoeval.pass.x.
      const std::vector<uint8_t> block =
          glsl_uniform_block(manifest_, params_, frame_, seed(), g, static_cast<int32_t>(i),
                             static_cast<int32_t>(shaders_.size()));
      d.uniforms[i].upload(block.data(), block.size());
    }
    prepared_for_ = &g;
  }

  EstimateResult run(const EstimateContext& context) override {
    const int index = context.frame ? context.frame->index : 0;
    const uint64_t offset = context.frame ? context.frame->seed_offset : 0;
    if (prepared_for_ != &context.gbuffer || !device_ || still_ != (context.frame == nullptr) ||
        frame_.index != index || frame_.seed_offset != offset)
      prepare(context);
    Device& d = *device_;
    const GBuffer& g = context.gbuffer;
    // aoeval_history: frame k - 1's final output, still in its ping image; zero on a still view,
    // at frame 0, and when frame k - 1 did not run on this device (a time-out gave a new one).
    // A second run of frame k keeps its history (frame k - 1's), so repeated runs agree.
    // aoeval_state follows the same rule (zeros, frame k - 1's, or frame k - 1's again).
    const History history = still_ || index == 0       ? History::clear
                            : last_frame_ == index - 1 ? History::copy
                            : last_frame_ == index     ? History::keep
                                                       : History::clear;
    const size_t last = (shaders_.size() - 1) % 2;
    // What the recording needs, by value: after a time-out the recording thread outlives this
    // call (and maybe the estimator); only `d`, then abandoned and never freed, is shared.
    struct Pass {
      std::string name;
      uint32_t groups_x, groups_y;
    };
    std::vector<Pass> passes;
    for (const PassShader& s : shaders_)
      passes.push_back({s.name,
                        vk::group_count(static_cast<uint32_t>(g.width), s.code.local_size[0]),
                        vk::group_count(static_cast<uint32_t>(g.height), s.code.local_size[1])});
    const bool bent = manifest_.bent;
    auto record = [&d, passes, bent, history, last](VkCommandBuffer cmd) {
      d.timer.reset(cmd);
      const VkClearColorValue zero{};
      VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      auto copy_image = [&](const vk::Image2D& from, const vk::Image2D& to) {
        VkImageCopy copy{};
        copy.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.dstSubresource = copy.srcSubresource;
        copy.extent = {static_cast<uint32_t>(to.width()), static_cast<uint32_t>(to.height()), 1};
        vkCmdCopyImage(cmd, from.handle(), VK_IMAGE_LAYOUT_GENERAL, to.handle(),
                       VK_IMAGE_LAYOUT_GENERAL, 1, &copy);
      };
      // aoeval_state: `state` is what the passes read and write; `state_saved` holds what frame
      // k - 1 left, so that a repeated frame k starts from it again.
      if (history == History::copy) {
        copy_image(d.ping[last], d.history);
        copy_image(d.state, d.state_saved);
        vk::pass_barrier(cmd);
      } else if (history == History::keep) {
        copy_image(d.state_saved, d.state);
        vk::pass_barrier(cmd);
      } else {
        for (const vk::Image2D* image : {&d.history, &d.state, &d.state_saved})
          vkCmdClearColorImage(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
      }
      // A frame's passes start from zeros, whatever the last frame left.
      for (const vk::Image2D* image : {&d.ping[0], &d.ping[1], &d.bent})
        if (image != &d.bent || bent)
          vkCmdClearColorImage(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
      vk::pass_barrier(cmd);
      for (size_t i = 0; i < passes.size(); ++i) {
        d.timer.begin(cmd, passes[i].name);
        d.pipelines[i]->dispatch(cmd, d.sets[i], static_cast<const void*>(nullptr), size_t{0},
                                 passes[i].groups_x, passes[i].groups_y);
        d.timer.end(cmd);
        vk::pass_barrier(cmd);
      }
    };
    submit_within_timeout(record);
    last_frame_ = still_ ? -1 : index;
    EstimateResult r;
    r.pass_ms = d.timer.read();
    if (!r.pass_ms.empty()) r.timing_source = "gpu-timestamps";
    r.ao = d.ping[last].download<float>();
    for (size_t k = 0; k < r.ao.size(); ++k) {
      if (!g.covered(k)) {
        r.ao[k] = 0.0f;
        continue;
      }
      // The same checks and range rule as a process plug-in's output (plugin_process.h).
      const float v = r.ao[k];
      if (!std::isfinite(v) || v < -kAoRangeSlack || v > 1.0f + kAoRangeSlack) {
        char where[96];
        std::snprintf(where, sizeof(where), " at covered pixel (%zu, %zu) of frame %d",
                      k % static_cast<size_t>(g.width), k / static_cast<size_t>(g.width), index);
        throw EstimatorUnavailable("plug-in " + manifest_.name + ": AO " +
                                   (std::isfinite(v) ? "= " + format_param_value(v) +
                                                           std::string(where) + " is outside [0, 1]"
                                                     : "is not finite" + std::string(where)));
      }
      r.ao[k] = std::clamp(v, 0.0f, 1.0f);
    }
    if (manifest_.bent) {
      const std::vector<float> b = d.bent.download<float>();
      const Camera& c = g.camera;
      for (const char* axis : {"bent.X", "bent.Y", "bent.Z"})
        r.extra_channels[axis].assign(g.pixel_count(), 0.0f);
      for (size_t k = 0; k < g.pixel_count(); ++k) {
        if (!g.covered(k)) continue;
        // eye -> world: x along right, y along up, z against forward.
        const glm::vec3 w = b[4 * k] * c.right + b[4 * k + 1] * c.up - b[4 * k + 2] * c.forward;
        r.extra_channels["bent.X"][k] = w.x;
        r.extra_channels["bent.Y"][k] = w.y;
        r.extra_channels["bent.Z"][k] = w.z;
      }
    }
    return r;
  }

 private:
  struct Device {
    vk::Context& vk;
    vk::Image2D depth, normal, position, ping[2], bent, noise, motion, disoccluded, history;
    vk::Image2D state, state_saved;    // aoeval_state, and frame k - 1's copy of it
    std::vector<vk::Buffer> uniforms;  // one per pass
    vk::PassTimer timer;
    std::vector<std::unique_ptr<vk::ComputePipeline>> pipelines;
    std::vector<VkDescriptorSet> sets;

    Device(vk::Context& context, int w, int h, uint32_t passes)
        : vk(context), timer(context, passes) {
      depth = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
      normal = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      position = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      for (auto& p : ping) p = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
      bent = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      noise = vk::Image2D(vk, kGlslNoiseSize, kGlslNoiseSize, VK_FORMAT_R32G32B32A32_SFLOAT);
      motion = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      disoccluded = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
      history = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
      state = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
      state_saved = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
    }

    // The frame's G-buffer in eye space, its motion and disocclusion (zeros on a still view).
    void upload(const GBuffer& g) {
      const Camera& c = g.camera;
      const size_t count = g.pixel_count();
      const bool moving = g.motion.size() == count && g.disoccluded.size() == count;
      std::vector<float> z(count), n(4 * count), p(4 * count), m(4 * count, 0.0f), dis(count, 0.0f);
      for (size_t k = 0; k < count; ++k) {
        const bool covered = g.covered(k);
        z[k] = covered ? g.depth[k] : 0.0f;
        const glm::vec3 d = g.position[k] - c.eye;
        const glm::vec3 pe(glm::dot(d, c.right), glm::dot(d, c.up), -glm::dot(d, c.forward));
        const glm::vec3 ne(glm::dot(g.normal[k], c.right), glm::dot(g.normal[k], c.up),
                           -glm::dot(g.normal[k], c.forward));
        for (int a = 0; a < 3; ++a) {
          n[4 * k + a] = covered ? ne[a] : 0.0f;
          p[4 * k + a] = covered ? pe[a] : 0.0f;
        }
        n[4 * k + 3] = covered ? 1.0f : 0.0f;
        p[4 * k + 3] = covered ? g.object_id[k] : -1.0f;
        if (moving && covered) {
          m[4 * k] = g.motion[k].x;
          m[4 * k + 1] = g.motion[k].y;
          dis[k] = g.disoccluded[k];
        }
      }
      depth.upload(z);
      normal.upload(n);
      position.upload(p);
      motion.upload(m);
      disoccluded.upload(dis);
    }
  };

  enum class History { clear, copy, keep };

  // A device of this size with the passes' pipelines and descriptor sets; frame k - 1's output is
  // not on it, so the next frame's history is zero.
  void make_device(int w, int h) {
    vk::Context& vk = plugin_context();
    on_lavapipe_ = vk.device_name().find("llvmpipe") != std::string::npos;
    device_ = std::make_unique<Device>(vk, w, h, static_cast<uint32_t>(shaders_.size()));
    Device& d = *device_;
    last_frame_ = -1;
    const size_t block_bytes = glsl_uniform_block_bytes(manifest_);
    for (size_t i = 0; i < shaders_.size(); ++i) {
      d.uniforms.emplace_back(vk, block_bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
      vk::SpirvCode code;
      code.words = shaders_[i].code.spirv.data();
      code.bytes = shaders_[i].code.spirv.size() * sizeof(uint32_t);
      auto pipeline = std::make_unique<vk::ComputePipeline>(
          vk, manifest_.name + " " + shaders_[i].name, code, kGlslBindings);
      // Ping-pong: pass k writes ping[k % 2] and reads the other.
      const vk::Image2D& out = d.ping[i % 2];
      const vk::Image2D& prev = d.ping[(i + 1) % 2];
      d.sets.push_back(
          pipeline->make_set({d.depth, d.normal, d.position, prev, out, d.bent, d.noise,
                              d.uniforms[i], d.motion, d.disoccluded, d.history, d.state}));
      d.pipelines.push_back(std::move(pipeline));
    }
  }

  // Submits the frame and waits for it at most the manifest's timeout_s. The wait runs on a
  // thread of its own because a driver may execute the work inside vkQueueSubmit (lavapipe may)
  // or never signal the fence; on a time-out that thread, the device objects and the context are
  // abandoned (see plugin_context()), and the frame is an EstimatorUnavailable: a skipped row.
  void submit_within_timeout(const std::function<void(VkCommandBuffer)>& record) {
    Device& d = *device_;
    auto done = std::make_shared<std::promise<void>>();
    std::future<void> finished = done->get_future();
    std::thread worker([&vk = d.vk, record, done] {
      try {
        vk.submit(record);
        done->set_value();
      } catch (...) {
        done->set_exception(std::current_exception());
      }
    });
    const auto limit = std::chrono::duration<double>(manifest_.timeout_s);
    if (finished.wait_for(limit) == std::future_status::timeout) {
      worker.detach();
      abandon_plugin_context(&d.vk);
      (void)device_.release();  // its objects belong to the abandoned device: never destroyed
      prepared_for_ = nullptr;
      throw EstimatorUnavailable("plug-in " + manifest_.name + " timed out after " +
                                 format_param_value(manifest_.timeout_s) +
                                 " s (its Vulkan device was abandoned; the next frame gets a new "
                                 "one)");
    }
    worker.join();
    finished.get();  // a VulkanError of the submit, rethrown here
  }

  // The noise seed: the parameter "seed" when the plug-in declares an integer one, plus the
  // frame's seed offset (the seed rule, CONTRACT §10: k, or 0 under "seed_per_frame": false),
  // wrapped to 32 bits; else 0. aoeval.params.seed holds the same value.
  int32_t seed() const {
    const nlohmann::json values = frame_param_values(manifest_, params_.json(), &frame_);
    if (!values.contains("seed") || !values["seed"].is_number_integer()) return 0;
    return static_cast<int32_t>(static_cast<uint32_t>(values["seed"].get<int64_t>()));
  }

  PluginManifest manifest_;
  ParamSet params_;
  std::vector<PassShader> shaders_;
  std::unique_ptr<Device> device_;
  const GBuffer* prepared_for_ = nullptr;
  FrameInfo frame_;      // the frame prepared for (index 0, no seed offset on a still view)
  bool still_ = true;    // prepared for a still view (EstimateContext::frame null)
  int last_frame_ = -1;  // the frame whose output the device's last ping image holds; -1 none
  std::vector<std::string> loop_risks_;
  bool on_lavapipe_ = false;
};

}  // namespace

std::unique_ptr<Estimator> make_glsl_estimator(const PluginManifest& m, const ParamSet& params) {
  return std::make_unique<GlslEstimator>(m, params);
}

}  // namespace aoeval
