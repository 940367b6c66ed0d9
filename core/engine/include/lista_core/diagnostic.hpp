// One problem found in a pipeline before it runs, with where it is.
#pragma once

#include <lista/error.hpp>

#include <string>
#include <vector>

namespace lista::core {

struct Diagnostic {
  SourceLocation where;
  std::string stage;    // stage id, "" for pipeline-wide problems
  std::string message;  // without the location
  // "file:line:col: stage 'id': message"
  std::string str() const;
};

// Messages quote what the user wrote (a key, a stage id, a value); one
// 10 MB key must not become 10 MB of stderr. Longer texts are cut here.
inline constexpr size_t kMaxDiagnosticText = 400;
std::string shortened(std::string text, size_t most = kMaxDiagnosticText);

struct Diagnostics {
  std::vector<Diagnostic> errors, warnings;
  bool ok() const { return errors.empty(); }
  void error(SourceLocation where, std::string stage, std::string message) {
    errors.push_back({std::move(where), shortened(std::move(stage), 80), shortened(std::move(message))});
  }
  void warning(SourceLocation where, std::string stage, std::string message) {
    warnings.push_back({std::move(where), shortened(std::move(stage), 80), shortened(std::move(message))});
  }
  // Orders errors and warnings as a reader meets them: by file (in order of
  // first mention), line, column; file-wide ones (line 0, e.g. a --set
  // naming no stage) first. The checks run stage by stage and pass by pass,
  // so they find problems out of order. Stable: ties keep their order.
  void sort_by_location();
  // The first error as a lista::Error (for callers that stop at one).
  Error first_error() const;
};

}  // namespace lista::core
