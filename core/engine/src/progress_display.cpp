#include "progress_display.hpp"

#include <algorithm>
#include <ostream>

namespace lista::core {

void ProgressDisplay::update(const std::string& stage, const std::string& what, uint64_t done, uint64_t total,
                             bool finished) {
  if (quiet_ || !tty_) return;  // progress is for people watching; logs get the info lines
  std::lock_guard<std::mutex> lock(mutex_);
  const double fraction = total ? std::min(1.0, double(done) / double(total)) : (finished ? 1.0 : 0.0);
  const int percent = static_cast<int>(fraction * 100.0);
  constexpr int width = 30;
  const int filled = static_cast<int>(fraction * width);
  out_ << "\r\033[K" << stage << ": " << what << " [" << std::string(filled, '#') << std::string(width - filled, ' ')
       << "] " << percent << "%";
  if (total) out_ << " (" << done << "/" << total << ")";
  if (finished) {
    out_ << "\n";
    bar_shown_ = false;
  } else {
    bar_shown_ = true;
  }
  out_.flush();
}

void ProgressDisplay::line(const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (bar_shown_) {
    out_ << "\r\033[K";
    bar_shown_ = false;
  }
  out_ << text << "\n";
  out_.flush();
}

void StageProgress::begin(const std::string& what, uint64_t total) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    what_ = what;
    total_ = total;
    done_ = 0;
    shown_step_ = 0;
  }
  display_.update(stage_, what, 0, total, false);
}

void StageProgress::advance(uint64_t n) {
  const uint64_t done = done_ += n;
  if (total_ == 0 || display_.quiet() || !display_.tty()) return;
  // At most 100 redraws of the bar per task.
  const int step = static_cast<int>(std::min<uint64_t>(100, done * 100 / total_));
  int shown = shown_step_.load();
  if (step <= shown) return;
  if (!shown_step_.compare_exchange_strong(shown, step)) return;
  std::string what;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    what = what_;
  }
  display_.update(stage_, what, done, total_, false);
}

void StageProgress::end() {
  if (display_.quiet() || !display_.tty()) return;
  std::string what;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    what = what_;
  }
  display_.update(stage_, what, total_ ? total_ : done_.load(), total_, true);
}

}  // namespace lista::core
