#include "metadata.hpp"

#include <lista/error.hpp>

#include <sstream>

namespace lista::bag::ros2 {
namespace {

struct Line {
  int number = 0;
  size_t indent = 0;
  std::string body;  // without indentation and trailing spaces
};

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// A scalar as rosbag2 writes it: plain, "double" or 'single' quoted.
std::string scalar(std::string v, const std::string& file, int line) {
  v = trim(v);
  if (!v.empty() && (v[0] == '"' || v[0] == '\'')) {
    if (v.size() < 2 || v.back() != v[0]) throw Error(file + ":" + std::to_string(line) + ": unterminated quoted value " + v);
    return v.substr(1, v.size() - 2);
  }
  if (const size_t hash = v.find(" #"); hash != std::string::npos) v = trim(v.substr(0, hash));
  return v;
}

}  // namespace

BagMetadata parse_metadata(const std::string& text, const std::string& file) {
  std::vector<Line> lines;
  std::istringstream in(text);
  std::string raw;
  for (int n = 1; std::getline(in, raw); ++n) {
    const std::string body = trim(raw);
    if (body.empty() || body[0] == '#') continue;
    lines.push_back({n, raw.find_first_not_of(" \t"), body});
  }
  // The keys wanted sit at the indentation of storage_identifier; the same
  // names deeper down (inside topics or files) are not theirs.
  size_t level = std::string::npos;
  for (const Line& l : lines)
    if (l.body.rfind("storage_identifier:", 0) == 0) {
      level = l.indent;
      break;
    }
  if (level == std::string::npos) throw Error(file + ": no storage_identifier: not a rosbag2 metadata.yaml");

  BagMetadata m;
  bool have_files = false;
  for (size_t i = 0; i < lines.size(); ++i) {
    const Line& l = lines[i];
    if (l.indent != level) continue;
    const size_t colon = l.body.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = l.body.substr(0, colon), value = l.body.substr(colon + 1);
    if (key == "storage_identifier") m.storage_identifier = scalar(value, file, l.number);
    else if (key == "compression_format") m.compression_format = scalar(value, file, l.number);
    else if (key == "compression_mode") m.compression_mode = scalar(value, file, l.number);
    else if (key == "relative_file_paths") {
      have_files = true;
      const std::string v = trim(value);
      if (!v.empty() && v[0] == '[') {  // flow style: [a.db3, b.db3]
        if (v.back() != ']') throw Error(file + ":" + std::to_string(l.number) + ": relative_file_paths: unterminated [");
        std::istringstream items(v.substr(1, v.size() - 2));
        for (std::string item; std::getline(items, item, ',');)
          if (!trim(item).empty()) m.relative_file_paths.push_back(scalar(item, file, l.number));
        continue;
      }
      // Block style: "- name" lines, indented or (valid YAML too) not.
      while (i + 1 < lines.size() && lines[i + 1].indent >= level && lines[i + 1].body.rfind("- ", 0) == 0) {
        ++i;
        m.relative_file_paths.push_back(scalar(lines[i].body.substr(2), file, lines[i].number));
      }
    }
  }

  if (m.storage_identifier != "sqlite3" && m.storage_identifier != "mcap")
    throw Error(file + ": unknown storage '" + m.storage_identifier + "' (LiSTA reads sqlite3 and mcap bags)");
  if (!m.compression_format.empty())
    throw Error(file + ": the bag is compressed with " + m.compression_format +
                (m.compression_mode.empty() ? "" : " (mode " + m.compression_mode + ")") +
                "; decompress it with `ros2 bag decompress` or re-record without compression");
  if (!have_files || m.relative_file_paths.empty()) throw Error(file + ": relative_file_paths names no storage file");
  for (const std::string& p : m.relative_file_paths)
    if (p.empty()) throw Error(file + ": relative_file_paths has an empty entry");
  return m;
}

std::string format_metadata(const std::string& storage_identifier, const std::string& relative_file,
                            const std::vector<TopicCount>& topics, int64_t start_ns, int64_t end_ns) {
  uint64_t total = 0;
  for (const TopicCount& t : topics) total += t.messages;
  const int64_t duration = total ? end_ns - start_ns : 0;
  std::ostringstream y;
  y << "rosbag2_bagfile_information:\n"
    << "  version: 5\n"
    << "  storage_identifier: " << storage_identifier << "\n"
    << "  duration:\n    nanoseconds: " << duration << "\n"
    << "  starting_time:\n    nanoseconds_since_epoch: " << start_ns << "\n"
    << "  message_count: " << total << "\n"
    << "  topics_with_message_count:" << (topics.empty() ? " []" : "") << "\n";
  for (const TopicCount& t : topics)
    y << "    - topic_metadata:\n"
      << "        name: " << t.name << "\n"
      << "        type: " << t.type << "\n"
      << "        serialization_format: cdr\n"
      << "        offered_qos_profiles: \"\"\n"
      << "      message_count: " << t.messages << "\n";
  y << "  compression_format: \"\"\n"
    << "  compression_mode: \"\"\n"
    << "  relative_file_paths:\n    - " << relative_file << "\n"
    << "  files:\n"
    << "    - path: " << relative_file << "\n"
    << "      starting_time:\n        nanoseconds_since_epoch: " << start_ns << "\n"
    << "      duration:\n        nanoseconds: " << duration << "\n"
    << "      message_count: " << total << "\n";
  return y.str();
}

}  // namespace lista::bag::ros2
