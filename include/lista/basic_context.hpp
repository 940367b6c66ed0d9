// A plain Context for tests and for embedding stages in other programs:
// logs to stderr at or above a level, no progress display, fixed threads and seed.
#pragma once

#include <lista/context.hpp>

#include <mutex>

namespace lista {

class BasicContext : public Context {
 public:
  explicit BasicContext(std::string stage_id = "test", int threads = 1, uint64_t seed = 0);
  const std::string& stage_id() const override { return stage_id_; }
  void log(LogLevel level, const std::string& message) override;
  Progress& progress() override;
  int threads() const override { return threads_; }
  uint64_t seed() const override { return seed_; }
  bool cancelled() const override { return cancel_requested; }
  void record(const std::string& key, double value) override;
  void note(const std::string& key, const std::string& text) override;
  RunInfo run_info() const override;

  LogLevel min_level = LogLevel::warning;
  bool cancel_requested = false;  // what cancelled() answers
  RunInfo info;  // what run_info() returns; recorded metrics land in info.metrics[stage_id], notes in info.notes[stage_id]
  std::vector<std::string> messages;  // every logged message, for assertions

 private:
  std::string stage_id_;
  int threads_;
  uint64_t seed_;
  mutable std::mutex mutex_;
};

}  // namespace lista
