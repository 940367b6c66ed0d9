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
extern "C" void on_stop_signal(int sig) {
  // Second signal: the user (or supervisor) means it; stop now.
  if (cancel_flag().exchange(true)) _exit(128 + sig);
  static const char msg[] = "\nlista-run: cancelling after the running stages notice (Ctrl-C again to stop now)\n";
  (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
}
}  // namespace

void install_sigint_handler() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  // SIGTERM is what timeout, systemd and docker send: it must not leave a
  // report.json from a run that did not finish, any more than Ctrl-C.
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

}  // namespace lista::core
