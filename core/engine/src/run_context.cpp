#include "run_context.hpp"

namespace lista::core {

const char* level_name(LogLevel level) {
  switch (level) {
    case LogLevel::debug: return "debug";
    case LogLevel::info: return "info";
    case LogLevel::warning: return "warning";
    case LogLevel::error: return "error";
  }
  return "?";
}

void RunContext::log(LogLevel level, const std::string& message) {
  if (level >= LogLevel::warning) {
    std::lock_guard<std::mutex> lock(run_.mutex);
    run_.info.warnings.push_back(stage_id_ + ": " + message);
  }
  if (level < run_.min_level) return;
  run_.display->line(std::string(level_name(level)) + ": " + stage_id_ + ": " + message);
}

void RunContext::record(const std::string& key, double value) {
  std::lock_guard<std::mutex> lock(run_.mutex);
  run_.info.metrics[stage_id_][key] = value;
}

void RunContext::note(const std::string& key, const std::string& text) {
  std::lock_guard<std::mutex> lock(run_.mutex);
  run_.info.notes[stage_id_][key] = text;
}

RunInfo RunContext::run_info() const {
  std::lock_guard<std::mutex> lock(run_.mutex);
  return run_.info;
}

}  // namespace lista::core
