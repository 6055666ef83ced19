// `aoeval gbuffer --scene S [--view V] [--res WxH] [--frame K] -o FILE.exr`: the shared G-buffer
// (CONTRACT §4).
#include <cstdio>

#include "base/errors.h"
#include "base/text_files.h"
#include "cmd/commands.h"
#include "scenes/corpus.h"
#include "scenes/gbuffer.h"
#include "scenes/sequence_frame.h"

namespace aoeval {

void add_gbuffer_command(CLI::App& app) {
  struct Options {
    std::string scene, view, res, output;
    int frame = 0;
  };
  static Options o;
  auto* cmd = app.add_subcommand("gbuffer", "the G-buffer every estimator and the reference share");
  cmd->add_option("--scene", o.scene, "corpus name or scene file")->required();
  cmd->add_option("--view", o.view, "view name (default: the scene's first view)");
  cmd->add_option("--res", o.res, "resolution WIDTHxHEIGHT (default: the view's)");
  cmd->add_option("--frame", o.frame,
                  "frame K of a sequence view (CONTRACT §10): adds motion.X, motion.Y, disoccluded")
      ->check(frame_number_check());
  cmd->add_option("-o,--output", o.output, "output OpenEXR file")->required();
  cmd->callback([] {
    install_interrupt_cleanup();  // Ctrl-C leaves no temporary (text_files.h)
    remove_dead_temporaries_of(o.output);
    const auto [w, h] = parse_resolution(o.res);
    Scene scene = load_scene(o.scene);
    const View& view = scene.view(o.view);
    const SequenceFrame frame = sequence_frame(scene, view, o.frame);
    const GBuffer g = render_frame_gbuffer(scene, view, o.frame, w, h);
    write_exr(o.output, gbuffer_to_image(g),
              frame_attributes(posed_scene(scene, frame), view, g.camera, o.frame));
  });
}

}  // namespace aoeval
