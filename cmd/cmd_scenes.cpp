// `aoeval scenes [list|show NAME|export NAME]`: the corpus, its sizes and its costs, and a scene as
// another renderer sees it.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/resolution.h"
#include "base/text_files.h"
#include "cmd/commands.h"
#include "harness/evaluation/progress.h"
#include "scenes/corpus.h"
#include "scenes/embree_scene.h"
#include "scenes/instances.h"
#include "scenes/scene_export.h"

namespace aoeval {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

long long peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

long long mesh_bytes(const Scene& s) {
  long long b = 0;
  for (const auto& o : s.objects)
    b += static_cast<long long>(o.mesh.positions.size() * sizeof(glm::vec3) +
                                o.mesh.normals.size() * sizeof(glm::vec3) +
                                o.mesh.triangles.size() * sizeof(glm::uvec3));
  return b;
}

std::string view_names(const Scene& s) {
  std::string v;
  for (const auto& view : s.views) v += (v.empty() ? "" : ",") + view.name;
  return v;
}

nlohmann::json vec(const glm::vec3& v) {
  return {v.x, v.y, v.z};
}

void list_scenes(bool json) {
  const auto names = corpus_names();
  nlohmann::json rows = nlohmann::json::array();
  Progress progress("scenes", names.size());
  if (!json) std::printf("%-22s %12s %8s  %s\n", "name", "triangles", "objects", "views");
  for (const auto& name : names) {
    Scene s = load_scene(name);
    progress.step(name);
    if (json) {
      rows.push_back({{"name", name},
                      {"triangles", s.triangle_count()},
                      {"objects", s.objects.size()},
                      {"views", view_names(s)}});
    } else {
      std::printf("%-22s %12zu %8zu  %s\n", name.c_str(), s.triangle_count(), s.objects.size(),
                  view_names(s).c_str());
      std::fflush(stdout);
    }
  }
  if (json) std::printf("%s\n", rows.dump(2).c_str());
}

void show_scene(const std::string& name, bool json) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene s = load_scene(name);
  const double load_ms = ms_since(t0);
  EmbreeScene es(s);
  const Bounds b = s.bounds();
  nlohmann::json j = {
      {"name", s.name},
      {"file", s.file},
      {"content_hash", hash_hex(s.content_hash())},
      {"triangles", s.triangle_count()},
      {"instanced_triangles", instanced_triangle_count(s)},
      {"instances", instance_count(s)},
      {"copies_bytes_estimate", estimated_bytes(s, true)},
      {"bounds", {{"lower", vec(b.lower)}, {"upper", vec(b.upper)}}},
      {"load_ms", load_ms},
      {"bvh_build_ms", es.build_ms()},
      {"mesh_bytes", mesh_bytes(s)},
      {"embree_bytes", es.memory_bytes()},
      {"peak_rss_bytes", peak_rss_bytes()},
  };
  for (const auto& o : s.objects) {
    nlohmann::json oj = {{"name", o.name},
                         {"role", role_name(o.role)},
                         {"source", o.source},
                         {"triangles", o.mesh.triangle_count()},
                         {"instances", o.instances.size()},
                         {"facts", o.facts}};
    if (!o.instance_names.empty()) oj["instance_names"] = o.instance_names;
    if (o.proxy) {
      nlohmann::json shapes = nlohmann::json::array();
      for (const auto& e : o.proxy->shapes)
        shapes.push_back({{"center", vec(e.center)}, {"radii", vec(e.radii)}});
      oj["proxy"] = {{"type", o.proxy->type}, {"shapes", shapes}};
    }
    if (o.density) oj["density"] = *o.density;
    j["objects"].push_back(oj);
  }
  for (const auto& v : s.views)
    j["views"].push_back({{"name", v.name},
                          {"eye", vec(v.eye)},
                          {"target", vec(v.target)},
                          {"up", vec(v.up)},
                          {"fov_y_deg", v.fov_y_deg},
                          {"width", v.width},
                          {"height", v.height}});
  if (json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("scene      %s\nfile       %s\nhash       %s\ntriangles  %zu\n", s.name.c_str(),
              s.file.c_str(), hash_hex(s.content_hash()).c_str(), s.triangle_count());
  if (has_instances(s))
    std::printf("instanced  %zu triangles as placed (%zu instances); as copies about %.1f GiB\n",
                instanced_triangle_count(s), instance_count(s),
                estimated_bytes(s, true) / 1073741824.0);
  std::printf("bounds     [%.3f %.3f %.3f] - [%.3f %.3f %.3f]\n", b.lower.x, b.lower.y, b.lower.z,
              b.upper.x, b.upper.y, b.upper.z);
  std::printf("load       %.1f ms (parse, read or generate, transform)\n", load_ms);
  std::printf("bvh build  %.1f ms (Embree, high quality, robust)\n", es.build_ms());
  std::printf("memory     meshes %.1f MiB, Embree %.1f MiB, peak RSS %.1f MiB\n",
              mesh_bytes(s) / 1048576.0, es.memory_bytes() / 1048576.0,
              peak_rss_bytes() / 1048576.0);
  std::printf("objects\n");
  for (const auto& o : s.objects) {
    std::printf("  %-16s %-7s %10zu tris  %s\n", o.name.c_str(), role_name(o.role),
                o.mesh.triangle_count(), o.source.c_str());
    if (!o.instances.empty())
      std::printf("  %-16s instances %zu (%zu triangles as placed)\n", "", o.instances.size(),
                  o.instances.size() * o.mesh.triangle_count());
    if (!o.instance_names.empty()) {  // glTF: the nodes sharing the mesh
      std::string names;
      for (const auto& n : o.instance_names) names += (names.empty() ? "" : ", ") + n;
      std::printf("  %-16s one mesh, placed as %s\n", "", names.c_str());
    }
    if (!o.facts.empty()) std::printf("  %-16s facts %s\n", "", o.facts.dump().c_str());
    if (o.proxy)
      std::printf("  %-16s proxy %s (%zu shape(s))\n", "", o.proxy->type.c_str(),
                  o.proxy->shapes.size());
    if (o.density) std::printf("  %-16s density %g\n", "", *o.density);
  }
  std::printf("views\n");
  for (const auto& v : s.views) {
    std::printf("  %-10s eye [%.2f %.2f %.2f] target [%.2f %.2f %.2f] fov %.1f deg %dx%d",
                v.name.c_str(), v.eye.x, v.eye.y, v.eye.z, v.target.x, v.target.y, v.target.z,
                v.fov_y_deg, v.width, v.height);
    if (v.sequence)
      std::printf(", sequence of %d frames at %g fps", v.frame_count(), v.sequence->fps);
    std::printf("\n");
  }
}

struct ExportOptions {
  std::string name, view, res, ply, camera;
};

// The triangles as the reference traces them (PLY) and the view's camera (JSON): what
// tools/cycles_ao_compare.py hands to Blender.
void export_scene(const ExportOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  Scene s = load_scene(o.name);
  const View& view = s.view(o.view);
  const Camera camera = make_camera(view, w, h);
  const std::string camera_text = camera_to_json(s, view, camera).dump(2) + "\n";
  write_scene_ply(s, o.ply);
  if (o.camera.empty()) return;
  try {  // both files or neither
    write_text(o.camera, camera_text);
  } catch (...) {
    std::remove(o.ply.c_str());
    throw;
  }
}

}  // namespace

void add_scenes_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("scenes", "the scene corpus: names, triangle counts, views, roles");
  cmd->require_subcommand(0, 1);
  static bool json = false;
  cmd->add_flag("--json", json, "print JSON instead of a table");
  auto* list =
      cmd->add_subcommand("list", "name, triangle count, objects and views of every scene");
  auto* show =
      cmd->add_subcommand("show", "one scene in detail, with load and BVH-build time and memory");
  static std::string name;
  show->add_option("NAME", name, "corpus name or scene file")->required();
  show->add_flag("--json", json, "print JSON instead of text");
  auto* exporter = cmd->add_subcommand(
      "export", "the world-space triangles (binary PLY) and a view's camera (JSON) of a scene");
  static ExportOptions export_options;
  exporter->add_option("NAME", export_options.name, "corpus name or scene file")->required();
  exporter->add_option("--out", export_options.ply, "output PLY file")->required();
  exporter->add_option("--camera", export_options.camera, "output JSON file: the view's camera");
  exporter->add_option("--view", export_options.view, "view name (default: the scene's first)");
  exporter->add_option("--res", export_options.res,
                       "resolution WIDTHxHEIGHT (default: the view's)");
  list->add_flag("--json", json, "print JSON instead of a table");
  cmd->callback([cmd, show, exporter] {
    if (exporter->parsed())
      export_scene(export_options);
    else if (show->parsed())
      show_scene(name, json);
    else
      list_scenes(json);
  });
}

}  // namespace aoeval
