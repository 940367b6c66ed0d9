// The registry: every stage a loaded plugin library declared, with its
// factory and the library it came from. A stage name is unique across all
// libraries; a second registration is an error naming both libraries.
#pragma once

#include <lista/plugin.hpp>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace lista::core {

struct RegisteredStage {
  StageInfo info;
  StageFactory factory;
  std::string library;  // path of the shared library ("" when added in-process)
};

class Registry : public Registrar {
 public:
  // Registrar: adds a stage from the library set by set_current_library().
  void add(StageInfo info, StageFactory factory) override;

  // The library whose register_stages is running (for error messages and records).
  void set_current_library(std::string path) { current_library_ = std::move(path); }

  // Libraries whose stages this registry holds (canonical paths), so that
  // loading one twice into the same registry adds nothing the second time.
  void mark_library_loaded(const std::string& path) { libraries_.insert(path); }
  bool has_library(const std::string& path) const { return libraries_.count(path) != 0; }

  // A library refused because it provides `name`, which an earlier one on
  // the search path already gave: the stage in use is find(name), and a
  // pipeline using it is warned that another library offered it too.
  void note_refused(const std::string& name, const std::string& library) { refused_[name].push_back(library); }
  const std::vector<std::string>& refused(const std::string& name) const;

  const RegisteredStage* find(const std::string& name) const;
  std::vector<std::string> names() const;  // sorted
  size_t size() const { return stages_.size(); }
  // Stage names close to `name` (edit distance), best first.
  std::vector<std::string> similar(const std::string& name) const;

 private:
  std::map<std::string, RegisteredStage> stages_;
  std::string current_library_;
  std::set<std::string> libraries_;
  std::map<std::string, std::vector<std::string>> refused_;
};

}  // namespace lista::core
