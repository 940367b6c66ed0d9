#include "process.hpp"

#include <lista_core/cancel.hpp>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <mutex>
#include <fstream>
#include <string>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace lista::core {

uint64_t peak_rss_bytes() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;  // reported in kB
  return 0;
}

void return_free_memory() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
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

// The running stages as text, for the crash handler: a fixed buffer, written
// under a lock, read (without one) only when the process is dying anyway.
char g_running[512] = "";
char g_program[64] = "lista";
std::mutex g_running_mutex;

extern "C" void on_crash(int sig) {
  static const char head[] = ": crashed (signal ";
  static const char mid[] = ") while running: ";
  static const char tail[] = "; a bug in that stage's plugin: rerun it alone, or under gdb, to see where\n";
  char num[4] = {char('0' + (sig / 10) % 10), char('0' + sig % 10), 0, 0};
  (void)!write(STDERR_FILENO, g_program, strnlen(g_program, sizeof g_program));
  (void)!write(STDERR_FILENO, head, sizeof head - 1);
  (void)!write(STDERR_FILENO, num, 2);
  const size_t running = strnlen(g_running, sizeof g_running);
  if (running > 0) {
    (void)!write(STDERR_FILENO, mid, sizeof mid - 1);
    (void)!write(STDERR_FILENO, g_running, running);
    (void)!write(STDERR_FILENO, tail, sizeof tail - 1);
  } else {
    static const char outside[] = ") outside any stage\n";
    (void)!write(STDERR_FILENO, outside, sizeof outside - 1);
  }
  signal(sig, SIG_DFL);  // die of the same signal (core dump, exit status)
  raise(sig);
}
}  // namespace

void set_running_stages(const std::string& text) {
  std::lock_guard<std::mutex> lock(g_running_mutex);
  const size_t n = std::min(text.size(), sizeof g_running - 1);
  std::memcpy(g_running, text.data(), n);
  g_running[n] = 0;
}

void install_crash_handler(const char* program) {
  std::strncpy(g_program, program, sizeof g_program - 1);
  struct sigaction sa {};
  sa.sa_handler = on_crash;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) sigaction(sig, &sa, nullptr);
}

void install_sigint_handler() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  // SIGTERM is what timeout, systemd and docker send: it must not leave a
  // report.json from a run that did not finish, any more than Ctrl-C.
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

}  // namespace lista::core
