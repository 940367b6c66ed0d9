#include <lista/error.hpp>

namespace lista {

std::string SourceLocation::str() const {
  if (file.empty()) return {};
  std::string s = file;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (column > 0) s += ":" + std::to_string(column);
  }
  return s;
}

Error::Error(std::string message) : std::runtime_error(message), message_(std::move(message)) {
  reformat();
}

Error& Error::at(SourceLocation location) {
  location_ = std::move(location);
  reformat();
  return *this;
}

Error& Error::in_stage(std::string stage_id, std::string plugin) {
  stage_id_ = std::move(stage_id);
  plugin_ = std::move(plugin);
  reformat();
  return *this;
}

void Error::reformat() {
  formatted_.clear();
  if (location_.known()) formatted_ += location_.str() + ": ";
  if (!stage_id_.empty()) {
    formatted_ += "stage '" + stage_id_ + "'";
    if (!plugin_.empty()) formatted_ += " (" + plugin_ + ")";
    formatted_ += ": ";
  }
  formatted_ += message_;
}

}  // namespace lista
