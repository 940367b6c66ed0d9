// The Context the executor gives each stage, over state shared by the run.
#pragma once

#include "progress_display.hpp"

#include <lista/context.hpp>

#include <atomic>
#include <mutex>

namespace lista::core {

// State of one run, shared by every stage's context.
struct RunState {
  RunInfo info;
  mutable std::mutex mutex;  // guards info
  ProgressDisplay* display = nullptr;
  LogLevel min_level = LogLevel::info;
  const std::atomic<bool>* cancel = nullptr;
};

class RunContext : public Context {
 public:
  RunContext(RunState& run, std::string stage_id, int threads)
      : run_(run), stage_id_(std::move(stage_id)), threads_(threads), progress_(*run.display, stage_id_) {}
  const std::string& stage_id() const override { return stage_id_; }
  void log(LogLevel level, const std::string& message) override;
  Progress& progress() override { return progress_; }
  int threads() const override { return threads_; }
  uint64_t seed() const override { return run_.info.seed; }
  bool cancelled() const override { return run_.cancel && run_.cancel->load(); }
  void record(const std::string& key, double value) override;
  void note(const std::string& key, const std::string& text) override;
  RunInfo run_info() const override;

 private:
  RunState& run_;
  std::string stage_id_;
  int threads_;
  StageProgress progress_;
};

const char* level_name(LogLevel level);

}  // namespace lista::core
