// The pages' one HTML writer (reports/html.h, issue 48): a runtime string cannot become markup.
#include "reports/html.h"

#include <gtest/gtest.h>

#include <string>

namespace aoeval {
namespace {

// By construction, checked by the compiler: a std::string or a char cannot be written into a page
// as markup; only a literal, an Html value or a number can. (A runtime const char* fails too, at
// Literal's consteval constructor, which a requires-expression cannot see.)
template <typename T>
concept Writable = requires(Html h, T v) {
  h << v;
};
static_assert(!Writable<std::string>);
static_assert(!Writable<const std::string&>);
static_assert(!Writable<std::string_view>);
static_assert(!Writable<char>);
static_assert(!Writable<double>);  // numbers with a format: number()
static_assert(Writable<Html>);
static_assert(Writable<int>);
static_assert(Writable<size_t>);

TEST(Html, TextEscapesEveryMarkupCharacter) {
  EXPECT_EQ(text("<script>alert(1)</script>").str(), "&lt;script&gt;alert(1)&lt;/script&gt;");
  EXPECT_EQ(text("\"><img src=x onerror=alert(2)>").str(),
            "&quot;&gt;&lt;img src=x onerror=alert(2)&gt;");
  EXPECT_EQ(attr("a'b&c").str(), "a&#39;b&amp;c");
  Html h;
  h << "<td>" << text("a<b") << "</td>" << 3;
  EXPECT_EQ(h.str(), "<td>a&lt;b</td>3");
}

TEST(Html, UrlKeepsPathsAndEncodesTheRest) {
  EXPECT_EQ(url("runs/r1/estimates/a__b-c_0123abcd.exr").str(),
            "runs/r1/estimates/a__b-c_0123abcd.exr");
  // No scheme survives (the colon is encoded), no quote, no space.
  EXPECT_EQ(url("javascript:alert(1)").str(), "javascript%3Aalert%281%29");
  EXPECT_EQ(url("x\" onerror=\"y").str(), "x%22%20onerror%3D%22y");
}

TEST(Html, ScriptJsonCannotEndTheScript) {
  const nlohmann::json j = {{"view", "</script><script>alert(3)</script><!--"}};
  const std::string s = script_json(j).str();
  EXPECT_EQ(s.find('<'), std::string::npos) << s;
  EXPECT_EQ(s.find('>'), std::string::npos) << s;
  EXPECT_EQ(nlohmann::json::parse(s), j);  // still the same JSON
  EXPECT_EQ(script_json(nlohmann::json("\xe2\x80\xa8")).str(), "\"\\u2028\"");
}

TEST(Html, NumbersAndThePolicy) {
  EXPECT_EQ(number(0.125).str(), "0.125");
  EXPECT_EQ(number(1.0 / 3.0, "%.2f").str(), "0.33");
  EXPECT_EQ(number(std::nan("")).str(), "&ndash;");
  const std::string csp = content_security_policy().str();
  EXPECT_NE(csp.find("script-src 'self';"), std::string::npos);
  // Scripts from files only: no 'unsafe-inline' (inline handlers) or 'unsafe-eval' for them.
  const size_t script = csp.find("script-src");
  ASSERT_NE(script, std::string::npos);
  EXPECT_EQ(csp.substr(script, csp.find(';', script) - script), "script-src 'self'");
}

}  // namespace
}  // namespace aoeval
