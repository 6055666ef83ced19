// `aoeval gbuffer --scene S [--view V] [--res WxH] -o FILE.exr`: the shared G-buffer (CONTRACT §4).
#include <cstdio>

#include "corpus.h"
#include "errors.h"
#include "gbuffer.h"
#include "harness/cli/commands.h"
#include "text_files.h"

namespace aoeval {

void add_gbuffer_command(CLI::App& app) {
  struct Options {
    std::string scene, view, res, output;
  };
  static Options o;
  auto* cmd = app.add_subcommand("gbuffer", "the G-buffer every estimator and the reference share");
  cmd->add_option("--scene", o.scene, "corpus name or scene file")->required();
  cmd->add_option("--view", o.view, "view name (default: the scene's first view)");
  cmd->add_option("--res", o.res, "resolution WIDTHxHEIGHT (default: the view's)");
  cmd->add_option("-o,--output", o.output, "output OpenEXR file")->required();
  cmd->callback([] {
    install_interrupt_cleanup();  // Ctrl-C leaves no temporary (text_files.h)
    remove_dead_temporaries_of(o.output);
    const auto [w, h] = parse_resolution(o.res);
    Scene scene = load_scene(o.scene);
    const View& view = scene.view(o.view);
    EmbreeScene es(scene);
    const Camera camera = make_camera(view, w, h);
    GBuffer g = render_gbuffer(es, camera);
    write_exr(o.output, gbuffer_to_image(g), gbuffer_attributes(scene, view, camera));
  });
}

}  // namespace aoeval
