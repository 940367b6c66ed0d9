#include "mission_file.hpp"

#include <lista/error.hpp>
#include <lista/toml_prechecks.hpp>

#include <toml.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lista::bag {

namespace {

// toml11's own message is several lines; the first names the problem.
std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

}  // namespace

MissionFile read_mission_file(const std::string& path, const BagOptions& defaults) {
  MissionFile out{defaults, std::nullopt};
  if (!std::filesystem::exists(path)) return out;
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw Error(path + ": cannot be read");
  const std::string s = text.str();
  if (s.size() > (1 << 16)) throw Error(path + ": over 64 KiB; a mission.toml holds a few keys");
  check_toml_utf8(s, path);
  check_toml_nesting(s, path);
  toml::value file;
  try {
    std::istringstream stream(s);
    file = toml::parse(stream, path);
  } catch (const std::exception& e) {
    throw Error(path + ": not valid TOML: " + first_line(e.what()));
  }
  if (!file.is_table()) throw Error(path + ": expected keys at the top level");
  const std::pair<const char*, std::string BagOptions::*> texts[] = {{"cloud_topic", &BagOptions::cloud_topic},
                                                                    {"poses", &BagOptions::poses},
                                                                    {"fixed_frame", &BagOptions::fixed_frame},
                                                                    {"body_frame", &BagOptions::body_frame}};
  for (const auto& [key, value] : file.as_table()) {
    auto where = [&, &key = key, &value = value](const std::string& what) {
      return Error(path + ":" + std::to_string(value.location().line()) + ": " + key + ": " + what);
    };
    if (key == "deskew") {
      if (!value.is_boolean()) throw where("expected true or false");
      out.options.deskew = value.as_boolean();
      continue;
    }
    if (key == "scan_spacing") {
      if (!value.is_floating() && !value.is_integer()) throw where("expected a number of metres");
      const double v = value.is_floating() ? value.as_floating() : double(value.as_integer());
      if (!(v >= 0.0 && v <= 100.0)) throw where("must be in [0, 100] m");
      out.scan_spacing = v;
      continue;
    }
    const auto it = std::find_if(std::begin(texts), std::end(texts), [&, &key = key](const auto& t) { return key == t.first; });
    if (it == std::end(texts))
      throw where("unknown key; a mission.toml knows cloud_topic, poses, fixed_frame, body_frame, deskew and scan_spacing");
    if (!value.is_string()) throw where("expected a string");
    out.options.*(it->second) = value.as_string().str;
  }
  return out;
}

}  // namespace lista::bag
