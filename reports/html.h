// The one HTML writer of every page aoeval writes (suite report, sweep page, sequences, G-buffer
// gallery, dashboard, figures index). Pages escape by construction (issue 48): markup is an `Html`
// value, and there are only three ways to make one:
//   - a string literal (`h << "<td>"`): the `Literal` it converts to has a consteval constructor,
//     so only text known when aoeval is compiled can become markup;
//   - text(s), attr(s), url(s), number(v): a runtime string enters only escaped for its context;
//   - other Html values (concatenation, the builders of the pages' pieces).
// Nothing takes a std::string as markup: `h << name` does not compile, so no name, however
// planted, can become a tag, an attribute or a script by forgetting to escape it.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace aoeval {

// A piece of markup written in aoeval's own source: only a compile-time constant converts.
struct Literal {
  const char* text;
  consteval Literal(const char* s) : text(s) {}  // NOLINT: implicit on purpose
};

class Html {
 public:
  Html() = default;
  explicit Html(Literal markup) : s_(markup.text) {}

  Html& operator<<(Literal markup) {
    s_ += markup.text;
    return *this;
  }
  Html& operator<<(const Html& markup) {
    s_ += markup.s_;
    return *this;
  }
  Html& operator<<(int v) { return append_integer(static_cast<long long>(v)); }
  Html& operator<<(long v) { return append_integer(static_cast<long long>(v)); }
  Html& operator<<(long long v) { return append_integer(v); }
  Html& operator<<(unsigned v) { return append_integer(static_cast<long long>(v)); }
  Html& operator<<(unsigned long v) { return append_integer(static_cast<long long>(v)); }
  Html& operator<<(unsigned long long v) { return append_integer(static_cast<long long>(v)); }
  // Not a character: a `char` would be text, spelt text(std::string(1, c)). A std::string or a
  // runtime const char* matches nothing: it must go through text(), attr() or url().
  Html& operator<<(char) = delete;

  Html& operator+=(const Html& markup) { return *this << markup; }
  Html& operator+=(Literal markup) { return *this << markup; }

  const std::string& str() const { return s_; }
  bool empty() const { return s_.empty(); }

 private:
  Html& append_integer(long long v) {
    s_ += std::to_string(v);
    return *this;
  }
  std::string s_;
  friend Html text(std::string_view);
  friend Html url(std::string_view);
  friend Html number(double, Literal);
  friend Html script_json(const nlohmann::json&);
};

inline Html operator+(Html a, const Html& b) {
  return a << b;
}
inline Html operator+(Html a, Literal b) {
  return a << b;
}

// Text for an element's content or a double- or single-quoted attribute's value: & < > " '
// escaped.
Html text(std::string_view s);
inline Html attr(std::string_view s) {
  return text(s);
}
// A relative link or image source (href, src, data-* naming a file): every byte outside
// [A-Za-z0-9/._~-] percent-encoded, so no scheme (javascript:, data:) and no quote survives.
Html url(std::string_view s);
// A number through printf's `format` (one conversion of a double); "&ndash;" when not finite.
Html number(double v, Literal format = "%.4g");
// JSON for a <script> element's data or a JavaScript string: every < > & and the line separators
// U+2028/2029 as \u escapes, so neither "</script>" nor "<!--" can end or bend the script.
Html script_json(const nlohmann::json& value);

// The page's Content-Security-Policy <meta>: scripts only from files (the viewer's, the
// dashboard's, the data scripts beside the page), no inline script and no inline event handler
// (onerror=...), no plug-ins, no network; styles may be inline (the pages' <style> blocks).
Html content_security_policy();

}  // namespace aoeval
