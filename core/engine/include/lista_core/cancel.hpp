// Ctrl-C: the first SIGINT (or SIGTERM, SIGHUP) sets a flag that running
// stages see through Context::cancelled(); a second one ends the process at
// once (exit 128 + signal).
#pragma once

#include <atomic>
#include <string>

namespace lista::core {

std::atomic<bool>& cancel_flag();
void install_sigint_handler();

// A crash (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT) inside a plugin kills the
// process; this handler first prints one line naming the stages that were
// running (the executor keeps that list current), then dies of the same
// signal. Call once, from the program, which the line names.
void install_crash_handler(const char* program);
// What the crash line names: "diff (volumetric.openvdb), ..."; the executor
// sets it whenever a stage starts or ends. Async-signal-safe to read.
void set_running_stages(const std::string& text);

}  // namespace lista::core
