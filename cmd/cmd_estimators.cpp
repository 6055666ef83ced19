// `aoeval estimators [list|show NAME]`: every estimator's declaration, as the registry holds it.
#include <cstdio>

#include "base/errors.h"

#include "cmd/commands.h"
#include "cmd/plugin_options.h"
#include "estimators/plugins/plugin_glsl.h"
#include "estimators/plugins/plugin_registry.h"
#include "estimators/registry.h"

namespace aoeval {

namespace {

std::string range_of(const ParamSpec& p) {
  if (p.type == ParamType::choice) {
    std::string s;
    for (const auto& c : p.choices) s += (s.empty() ? "" : "|") + c;
    return s;
  }
  if (p.type == ParamType::boolean) return "true|false";
  return "[" + format_param_value(p.min) + ", " + format_param_value(p.max) + "]" +
         (p.log_scale ? " log" : "");
}

nlohmann::json declaration(const EstimatorInfo& e) {
  nlohmann::json params = nlohmann::json::array();
  for (const auto& p : e.params) {
    nlohmann::json j = {{"name", p.name},
                        {"type", param_type_name(p.type)},
                        {"default", p.default_value},
                        {"unit", p.unit},
                        {"meaning", p.meaning},
                        {"scale", p.log_scale ? "log" : "lin"}};
    if (p.type == ParamType::choice) j["choices"] = p.choices;
    if (p.type == ParamType::real || p.type == ParamType::integer) j["range"] = {p.min, p.max};
    params.push_back(j);
  }
  nlohmann::json inputs = nlohmann::json::array();
  for (auto i : e.inputs) inputs.push_back(input_name(i));
  const ParamSet defaults = resolve_params(e.name, e.params, nlohmann::json::object(), e.name);
  return {{"name", e.name},
          {"summary", e.summary},
          {"paper", e.paper},
          {"backend", backend_name(e.backend)},
          {"kind", e.kind},
          {"folder", e.folder},
          {"inputs", inputs},
          {"definition", e.definition_doc},
          {"definition_at_defaults", e.definition(defaults).to_json()},
          {"params", params}};
}

void show(const EstimatorInfo& e) {
  const nlohmann::json d = declaration(e);
  std::printf("%s: %s\n  paper       %s\n  backend     %s\n  kind        %s%s\n  inputs      ",
              e.name.c_str(), e.summary.c_str(), e.paper.c_str(), backend_name(e.backend),
              e.kind.c_str(), e.folder.empty() ? "" : (" (" + e.folder + ")").c_str());
  for (size_t i = 0; i < e.inputs.size(); ++i)
    std::printf("%s%s", i ? ", " : "", input_name(e.inputs[i]));
  std::printf("\n  definition  %s (at defaults: %s)\n", e.definition_doc.c_str(),
              d["definition_at_defaults"].dump().c_str());
  std::printf(
      "  AO falloffs: none = occluders closer than dmax count fully; linear rho(x) = x;\n"
      "  sqrt rho(x) = sqrt(x); exp rho(x) = (1 - e^(-4x)) / (1 - e^(-4)); power:K rho(x) = x^K\n"
      "  (K > 0; power:1 is linear, power:0.5 is sqrt); an occluder at distance d < dmax weighs\n"
      "  1 - rho(d / dmax) (CONTRACT §3).\n");
  std::printf("  parameters\n    %-12s %-8s %-10s %-22s %-12s %s\n", "name", "type", "default",
              "range", "unit", "meaning");
  for (const auto& p : e.params)
    std::printf("    %-12s %-8s %-10s %-22s %-12s %s\n", p.name.c_str(), param_type_name(p.type),
                format_param_value(p.default_value).c_str(), range_of(p).c_str(), p.unit.c_str(),
                p.meaning.c_str());
}

}  // namespace

void add_estimators_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("estimators", "every estimator with its parameters and AO definition");
  cmd->require_subcommand(0, 1);
  static bool json = false;
  static std::string name;
  cmd->add_flag("--json", json, "print JSON");
  auto* list = cmd->add_subcommand("list", "one line per estimator");
  list->add_flag("--json", json, "print JSON");
  auto* show_cmd = cmd->add_subcommand("show", "one estimator's full declaration");
  show_cmd->add_option("NAME", name, "estimator name")->required();
  show_cmd->add_flag("--json", json, "print JSON");
  auto* abi = cmd->add_subcommand(
      "abi",
      "the plug-in ABI: GLSL bindings and uniform block, the process protocols (with NAME: that "
      "GLSL plug-in's preamble)");
  abi->add_option("NAME", name, "a GLSL plug-in");
  for (CLI::App* c : {cmd, list, show_cmd, abi}) add_plugins_option(c);
  cmd->callback([show_cmd, abi] {
    if (abi->parsed()) {
      if (name.empty()) {
        std::printf("%s", plugin_abi_text().c_str());
        return;
      }
      const EstimatorInfo& e = find_estimator(name);
      if (e.kind != "glsl") throw InputError("estimators abi: " + name + " is not a GLSL plug-in");
      std::printf("#version 450\n%s", glsl_abi_preamble(e.params).c_str());
      return;
    }
    if (show_cmd->parsed()) {
      const EstimatorInfo& e = find_estimator(name);
      if (json)
        std::printf("%s\n", declaration(e).dump(2).c_str());
      else
        show(e);
      return;
    }
    nlohmann::json all = nlohmann::json::array();
    for (const auto& e : estimator_registry()) {
      if (json) {
        all.push_back(declaration(e));
      } else {
        std::string params;
        for (const auto& p : e.params) params += (params.empty() ? "" : " ") + p.name;
        std::printf("%-16s %-8s %-7s %-52s params: %s\n", e.name.c_str(), e.kind.c_str(),
                    backend_name(e.backend), e.summary.c_str(), params.c_str());
      }
    }
    if (json) std::printf("%s\n", all.dump(2).c_str());
  });
}

}  // namespace aoeval
