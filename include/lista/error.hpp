// The one error type of LiSTA. It carries where the problem is (stage id,
// plugin, TOML file/line/column) so that every message can point the user at
// the line to fix. Formatted as
//   pipeline.toml:12:3: stage 'diff' (volumetric.octomap): resolution must be > 0
#pragma once

#include <stdexcept>
#include <string>

namespace lista {

struct SourceLocation {
  std::string file;  // empty when unknown
  int line = 0;      // 1-based, 0 when unknown
  int column = 0;    // 1-based, 0 when unknown
  bool known() const { return !file.empty(); }
  std::string str() const;  // "file:line:col", "file:line", "file" or ""
};

class Error : public std::runtime_error {
 public:
  explicit Error(std::string message);

  // Fill in context; each returns *this so a catch block can rethrow enriched.
  Error& at(SourceLocation location);
  Error& in_stage(std::string stage_id, std::string plugin);

  const std::string& message() const { return message_; }
  const std::string& stage_id() const { return stage_id_; }
  const std::string& plugin() const { return plugin_; }
  const SourceLocation& location() const { return location_; }

  const char* what() const noexcept override { return formatted_.c_str(); }

 private:
  void reformat();
  std::string message_, stage_id_, plugin_, formatted_;
  SourceLocation location_;
};

// Thrown by Context::throw_if_cancelled() after Ctrl-C.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled by user") {}
};

}  // namespace lista
