// What the figure tests read from a caption (figure.cpp's caption_text): the mark of a check and
// the verdict, which must follow from the marks by figure.cpp's rule (all pass: "reproduced",
// none: "not reproduced", else "partly reproduced"). Finding "Verdict: " or a check's words
// anywhere passed whatever the verdict said.
#pragma once

#include <string>

namespace aoeval::figures::captions {

// "pass" or "fail" for the check line whose rule starts with `rule`; "" when there is no such line.
inline std::string check_mark(const std::string& caption, const std::string& rule) {
  for (const char* mark : {"pass", "fail"})
    if (caption.find(std::string("\n  [") + mark + "] " + rule) != std::string::npos) return mark;
  return "";
}

// The verdict the caption's check lines call for, as the caption prints it: "\nVerdict: <v> (".
inline std::string expected_verdict_line(const std::string& caption) {
  size_t passed = 0, failed = 0;
  for (size_t at = 0; (at = caption.find("\n  [pass] ", at)) != std::string::npos; ++at) ++passed;
  for (size_t at = 0; (at = caption.find("\n  [fail] ", at)) != std::string::npos; ++at) ++failed;
  const char* verdict = passed + failed == 0 ? "not reproduced"
                        : failed == 0        ? "reproduced"
                        : passed == 0        ? "not reproduced"
                                             : "partly reproduced";
  return std::string("\nVerdict: ") + verdict + " (";
}

}  // namespace aoeval::figures::captions
