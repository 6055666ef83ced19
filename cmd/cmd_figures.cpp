// `aoeval figures [NAME...|--all] [--out DIR] [--quick]`: reproductions of the seed papers' figures
// and tables (harness/figures/). Each figure writes <name>.png, <name>.csv and the caption
// <name>.txt; index.html lists every figure present in the folder. A figure that cannot be produced
// (an exception in its function) gets a caption saying why, and the command exits 1; unknown names
// exit 2 with the list of names.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "cmd/commands.h"
#include "harness/evaluation/progress.h"
#include "harness/figures/figure.h"
#include "reports/html.h"
#include "reports/page_assets.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

using namespace aoeval::figures;

struct FiguresOptions {
  std::vector<std::string> names;
  bool all = false, quick = false, list = false;
  std::string out_dir = "out/figures";
};

std::string known_names() {
  std::string s;
  for (const auto& f : figure_registry()) s += std::string(s.empty() ? "" : ", ") + f.name;
  return s;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// The verdict a caption states (caption_text's "Verdict: NAME (rule)." line), "not produced" for
// a figure that failed, "" when the caption has neither.
std::string verdict_in(const std::string& caption) {
  const std::string key = "\nVerdict: ";
  const size_t at = caption.find(key);
  if (at == std::string::npos)
    return caption.find("\nNot produced: ") != std::string::npos ? "not produced" : "";
  const size_t from = at + key.size();
  return caption.substr(from, caption.find_first_of("(\n", from) - from - 1);
}

// Every registered figure whose caption is in the folder, in registry order, with its verdict.
void write_index(const std::string& out_dir) {
  Html h;  // reports/html.h: every name and caption is text
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">" << content_security_policy()
    << "<title>aoeval figures</title>\n"
    << page_stylesheet(out_dir, "figures.css")
    << "</head><body>\n"
       "<h1>Reproductions of the seed papers' figures</h1>\n<ul>\n";
  std::vector<const Figure*> present;
  for (const auto& f : figure_registry())
    if (fs::exists(fs::path(out_dir) / (f.name + ".txt"))) present.push_back(&f);
  for (const auto* f : present) {
    const std::string verdict = verdict_in(read_file(fs::path(out_dir) / (f->name + ".txt")));
    h << "<li><a href=\"#" << attr(f->name) << "\">" << text(f->name) << "</a> — ";
    if (!verdict.empty()) h << "<b class=\"verdict\">" << text(verdict) << "</b> — ";
    h << text(f->source) << "</li>\n";
  }
  h << "</ul>\n";
  for (const auto* f : present) {
    const fs::path dir(out_dir);
    h << "<h2 id=\"" << attr(f->name) << "\">" << text(f->name) << "</h2>\n";
    for (const auto& entry : {f->name + ".png", f->name + "-plot.png", f->name + "-images.png"})
      if (fs::exists(dir / entry))
        h << "<p><img src=\"" << url(entry) << "\" loading=\"lazy\" alt=\"" << attr(entry)
          << "\"></p>\n";
    if (fs::exists(dir / (f->name + ".csv")))
      h << "<p><a href=\"" << url(f->name + ".csv") << "\">numbers (CSV)</a></p>\n";
    h << "<pre>" << text(read_file(dir / (f->name + ".txt"))) << "</pre>\n";
  }
  h << "</body></html>\n";
  write_text((fs::path(out_dir) / "index.html").string(), h.str());
}

void remove_outputs(const std::string& out_dir, const std::string& name) {
  for (const auto& entry : fs::directory_iterator(out_dir)) {
    const std::string file = entry.path().filename().string();
    if (file.rfind(name + ".", 0) == 0 || file.rfind(name + "-", 0) == 0) fs::remove(entry.path());
  }
}

void run_figures(const FiguresOptions& o) {
  if (o.list) {
    for (const auto& f : figure_registry())
      std::printf("%-22s %s\n", f.name.c_str(), f.source.c_str());
    return;
  }
  std::vector<const Figure*> chosen;
  if (o.all)
    for (const auto& f : figure_registry()) chosen.push_back(&f);
  for (const auto& name : o.names) {
    const Figure* f = find_figure(name);
    if (!f) throw InputError("unknown figure '" + name + "'; known: " + known_names());
    chosen.push_back(f);
  }
  if (chosen.empty())
    throw InputError("name one or more figures or pass --all; known: " + known_names());
  fs::create_directories(o.out_dir);
  ReferenceSpec reference;
  if (o.quick) reference.spp = 64;
  EvaluationSession session(reference, TimingSpec{0, 1});
  FigureContext ctx;
  ctx.out_dir = o.out_dir;
  ctx.quick = o.quick;
  ctx.session = &session;
  int failed = 0;
  Progress progress("figures", chosen.size());
  for (const Figure* f : chosen) {
    const fs::path dir(o.out_dir);
    try {
      const FigureResult r = f->make(ctx);
      write_text((dir / (f->name + ".csv")).string(), to_csv(r.table));
      write_text((dir / (f->name + ".txt")).string(), caption_text(*f, r));
      std::printf("%-20s %-18s %s\n", f->name.c_str(), verdict_name(verdict_of(r.checks)),
                  (dir / (f->name + ".png")).string().c_str());
    } catch (const std::exception& e) {
      ++failed;
      remove_outputs(o.out_dir, f->name);
      write_text((dir / (f->name + ".txt")).string(), f->name + " — " + f->source +
                                                          "\n\nClaim: " + f->claim +
                                                          "\n\nNot produced: " + e.what() + "\n");
      std::printf("%-20s %-18s %s\n", f->name.c_str(), "not produced", e.what());
    }
    std::fflush(stdout);
    progress.step(f->name);
  }
  write_index(o.out_dir);
  std::printf("%s\n", (fs::path(o.out_dir) / "index.html").string().c_str());
  if (failed) throw ExitStatus{1};
}

}  // namespace

void add_figures_command(CLI::App& app) {
  static FiguresOptions o;
  auto* cmd = app.add_subcommand(
      "figures", "reproductions of the seed papers' figures and tables (PNG, CSV, caption)");
  cmd->add_option("names", o.names, "figure names (see --list)");
  cmd->add_flag("--all", o.all, "every figure");
  cmd->add_flag("--quick", o.quick, "tiny resolutions and 64-spp references (for tests)");
  cmd->add_flag("--list", o.list, "list the figures and exit");
  cmd->add_option("--out", o.out_dir, "output folder");
  cmd->callback([] { run_figures(o); });
}

}  // namespace aoeval
