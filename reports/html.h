// Small helpers shared by every HTML page aoeval writes (suite report, G-buffer gallery,
// dashboard, figures index).
#pragma once

#include <string>

namespace aoeval {

// Text safe inside HTML elements and double-quoted attributes: & < > " escaped.
std::string html_escape(const std::string& text);

}  // namespace aoeval
