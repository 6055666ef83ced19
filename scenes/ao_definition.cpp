#include "scenes/ao_definition.h"

#include <charconv>
#include <cstdlib>
#include <sstream>

#include "base/errors.h"

namespace aoeval {

const char* weighting_name(Weighting w) {
  return w == Weighting::cosine ? "cosine" : "uniform";
}

Falloff Falloff::power(double k) {
  if (!(k > 0.0) || !std::isfinite(k)) throw InputError("power:K needs K a positive finite number");
  if (k == 1.0) return Falloff::linear;
  if (k == 0.5) return Falloff::sqrt;
  return Falloff{Kind::power, k};
}

std::string falloff_name(Falloff f) {
  switch (f.kind) {
    case Falloff::Kind::none:
      return "none";
    case Falloff::Kind::linear:
      return "linear";
    case Falloff::Kind::sqrt:
      return "sqrt";
    case Falloff::Kind::exp:
      return "exp";
    case Falloff::Kind::power: {
      char k[32];  // shortest text that reads back as the same double: one name per definition
      const auto end = std::to_chars(k, k + sizeof(k), f.k).ptr;
      return "power:" + std::string(k, end);
    }
  }
  return "none";
}

Weighting parse_weighting(const std::string& text, const std::string& option) {
  if (text == "cosine") return Weighting::cosine;
  if (text == "uniform") return Weighting::uniform;
  throw InputError(option + ": '" + text + "' is not one of: cosine, uniform");
}

Falloff parse_falloff(const std::string& text, const std::string& option) {
  for (Falloff f : {Falloff::none, Falloff::linear, Falloff::sqrt, Falloff::exp})
    if (text == falloff_name(f)) return f;
  const std::string prefix = "power:";
  if (text.compare(0, prefix.size(), prefix) == 0) {
    const std::string k = text.substr(prefix.size());
    double v = 0.0;
    const auto [end, ec] = std::from_chars(k.data(), k.data() + k.size(), v);
    if (k.empty() || ec != std::errc() || end != k.data() + k.size() || !std::isfinite(v) ||
        !(v > 0.0))
      throw InputError(option + ": '" + text + "': K in power:K must be a positive finite number");
    return Falloff::power(v);
  }
  throw InputError(option + ": '" + text + "' is not one of: none, linear, sqrt, exp, power:K");
}

double parse_dmax(const std::string& text, const std::string& option) {
  if (text.empty() || text == "inf" || text == "none")
    return std::numeric_limits<double>::infinity();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v) || v <= 0.0)
    throw InputError(option + ": expected a positive distance or 'inf', got '" + text + "'");
  return v;
}

void validate_definition(const AoDefinition& d) {
  if (!(d.dmax > 0.0)) throw InputError("--dmax: must be positive");
  if (d.falloff != Falloff::none && !d.bounded())
    throw InputError(std::string("--falloff ") + falloff_name(d.falloff) +
                     " needs a finite --dmax (the falloff is a function of d / dmax)");
}

nlohmann::json AoDefinition::to_json() const {
  return {{"weighting", weighting_name(weighting)},
          {"dmax", bounded() ? nlohmann::json(dmax) : nlohmann::json(nullptr)},
          {"falloff", falloff_name(falloff)}};
}

std::string AoDefinition::label() const {
  std::ostringstream os;
  os << weighting_name(weighting);
  if (bounded()) os << "/dmax:" << dmax;
  if (falloff != Falloff::none) os << "/" << falloff_name(falloff);
  return os.str();
}

}  // namespace aoeval
