// Progress on stderr: an updating bar on a TTY; nothing when stderr is not
// a TTY (logs keep the stages' info lines) or when quiet. Shared by all
// running stages.
#pragma once

#include <lista/context.hpp>

#include <atomic>
#include <chrono>
#include <iosfwd>
#include <mutex>
#include <string>

namespace lista::core {

class ProgressDisplay {
 public:
  ProgressDisplay(std::ostream& out, bool tty, bool quiet) : out_(out), tty_(tty), quiet_(quiet) {}
  void update(const std::string& stage, const std::string& what, uint64_t done, uint64_t total, bool finished);
  // A log line; clears a bar in progress first.
  void line(const std::string& text);
  bool tty() const { return tty_; }
  bool quiet() const { return quiet_; }

 private:
  std::ostream& out_;
  bool tty_, quiet_;
  bool bar_shown_ = false;
  std::mutex mutex_;
};

// The Progress of one stage, forwarding to the display.
class StageProgress : public Progress {
 public:
  StageProgress(ProgressDisplay& display, std::string stage) : display_(display), stage_(std::move(stage)) {}
  void begin(const std::string& what, uint64_t total) override;
  void advance(uint64_t n = 1) override;
  void end() override;

 private:
  ProgressDisplay& display_;
  std::string stage_, what_;
  uint64_t total_ = 0;
  std::atomic<uint64_t> done_{0};
  std::atomic<int> shown_step_{-1};  // last displayed step, to throttle output
  std::mutex mutex_;
};

}  // namespace lista::core
