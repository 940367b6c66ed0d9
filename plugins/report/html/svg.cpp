#include "svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lista::report {

std::string escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string fmt(double value, int decimals) {
  if (!std::isfinite(value)) return "nan";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (uint32_t(bytes[i]) << 16) | (uint32_t(bytes[i + 1]) << 8) | bytes[i + 2];
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint32_t(bytes[i]) << 16;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = (uint32_t(bytes[i]) << 16) | (uint32_t(bytes[i + 1]) << 8);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

std::string Rgb::css() const {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
  return buf;
}

Rgb status_colour(const std::string& status) {
  if (status == "removed") return {214, 39, 40};
  if (status == "added") return {44, 160, 44};
  return {31, 119, 180};  // moved
}

Rgb palette(int index) {
  // Red, green and blue mean removed, added and moved on this page: groups
  // take the other categorical colours.
  static const Rgb colours[] = {{148, 103, 189}, {255, 127, 14}, {140, 86, 75}, {227, 119, 194},
                                {188, 189, 34},  {23, 190, 207}, {127, 127, 127}, {0, 0, 0},
                                {255, 187, 120}, {197, 176, 213}};
  if (index < 0) return {90, 90, 90};
  return colours[index % 10];
}

Rgb heat(double t) {
  t = std::clamp(t, 0.0, 1.0);
  // white -> dark purple: no status colour (red removed, green added, blue
  // moved) means similarity; readable on screen and in print.
  const double r = 250 - t * 166, g = 250 - t * 200, b = 252 - t * 92;
  return {uint8_t(r), uint8_t(g), uint8_t(b)};
}

}  // namespace lista::report
