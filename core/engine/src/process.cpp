#include "process.hpp"

#include <lista_core/cancel.hpp>

#include <csignal>
#include <fstream>
#include <string>
#include <unistd.h>

namespace lista::core {

uint64_t peak_rss_bytes() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;  // reported in kB
  return 0;
}

std::atomic<bool>& cancel_flag() {
  static std::atomic<bool> flag{false};
  return flag;
}

namespace {
extern "C" void on_sigint(int) {
  // Second Ctrl-C: the user means it; stop now.
  if (cancel_flag().exchange(true)) _exit(130);
  static const char msg[] = "\nlista-run: cancelling after the running stages notice (Ctrl-C again to stop now)\n";
  (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
}
}  // namespace

void install_sigint_handler() {
  struct sigaction sa {};
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
}

}  // namespace lista::core
