#include <lista/basic_context.hpp>

#include <iostream>

namespace lista {

namespace {
class SilentProgress : public Progress {
 public:
  void begin(const std::string&, uint64_t) override {}
  void advance(uint64_t) override {}
  void end() override {}
};
const char* level_name(LogLevel l) {
  switch (l) {
    case LogLevel::debug: return "debug";
    case LogLevel::info: return "info";
    case LogLevel::warning: return "warning";
    case LogLevel::error: return "error";
  }
  return "?";
}
}  // namespace

BasicContext::BasicContext(std::string stage_id, int threads, uint64_t seed)
    : stage_id_(std::move(stage_id)), threads_(threads < 1 ? 1 : threads), seed_(seed) {
  info.seed = seed;
  info.threads = threads_;
}

void BasicContext::log(LogLevel level, const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  messages.push_back(message);
  if (level >= min_level) std::cerr << level_name(level) << ": " << stage_id_ << ": " << message << "\n";
}

Progress& BasicContext::progress() {
  static SilentProgress silent;
  return silent;
}

void BasicContext::record(const std::string& key, double value) {
  std::lock_guard<std::mutex> lock(mutex_);
  info.metrics[stage_id_][key] = value;
}

void BasicContext::note(const std::string& key, const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  info.notes[stage_id_][key] = text;
}

RunInfo BasicContext::run_info() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return info;
}

}  // namespace lista
