// Tiny helpers for writing SVG and HTML text safely.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lista::report {

std::string escape(const std::string& text);  // HTML/XML text and attribute escaping
std::string fmt(double value, int decimals = 2);
std::string base64(const std::vector<uint8_t>& bytes);

struct Rgb {
  uint8_t r, g, b;
  std::string css() const;  // "#rrggbb"
};
Rgb status_colour(const std::string& status);  // removed red, added green, moved blue
Rgb palette(int index);                        // distinct colours for groups
Rgb heat(double t);                            // t in [0,1]: white -> dark red

}  // namespace lista::report
