#include "reports/html.h"

#include <cmath>
#include <cstdio>

namespace aoeval {

Html text(std::string_view s) {
  Html h;
  h.s_.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        h.s_ += "&amp;";
        break;
      case '<':
        h.s_ += "&lt;";
        break;
      case '>':
        h.s_ += "&gt;";
        break;
      case '"':
        h.s_ += "&quot;";
        break;
      case '\'':
        h.s_ += "&#39;";
        break;
      default:
        h.s_ += c;
    }
  }
  return h;
}

Html url(std::string_view s) {
  static const char* kHex = "0123456789ABCDEF";
  Html h;
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if ((u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') || c == '/' ||
        c == '.' || c == '_' || c == '~' || c == '-') {
      h.s_ += c;
    } else {
      h.s_ += '%';
      h.s_ += kHex[u >> 4];
      h.s_ += kHex[u & 15];
    }
  }
  return h;
}

Html number(double v, Literal format) {
  Html h;
  if (!std::isfinite(v)) {
    h.s_ = "&ndash;";
    return h;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, format.text, v);
  // A number's text: digits, sign, point, exponent; anything else would be the format's fault.
  for (const char* p = buf; *p; ++p) h.s_ += text(std::string_view(p, 1)).s_;
  return h;
}

Html script_json(const nlohmann::json& value) {
  const std::string dumped = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  Html h;
  h.s_.reserve(dumped.size());
  for (size_t i = 0; i < dumped.size(); ++i) {
    const char c = dumped[i];
    if (c == '<') {
      h.s_ += "\\u003c";
    } else if (c == '>') {
      h.s_ += "\\u003e";
    } else if (c == '&') {
      h.s_ += "\\u0026";
    } else if (c == '\xe2' && i + 2 < dumped.size() && dumped[i + 1] == '\x80' &&
               (dumped[i + 2] == '\xa8' || dumped[i + 2] == '\xa9')) {
      h.s_ += dumped[i + 2] == '\xa8' ? "\\u2028" : "\\u2029";
      i += 2;
    } else {
      h.s_ += c;
    }
  }
  return h;
}

Html content_security_policy() {
  return Html(
      "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
      "script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
      "media-src 'self' blob:; object-src 'none'; base-uri 'none'; form-action 'none'\">\n");
}

}  // namespace aoeval
