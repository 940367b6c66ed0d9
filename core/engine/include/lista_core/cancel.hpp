// Ctrl-C: the first SIGINT (or SIGTERM, SIGHUP) sets a flag that running
// stages see through Context::cancelled(); a second one ends the process at
// once (exit 128 + signal).
#pragma once

#include <atomic>

namespace lista::core {

std::atomic<bool>& cancel_flag();
void install_sigint_handler();

}  // namespace lista::core
