// Ctrl-C: the first SIGINT sets a flag that running stages see through
// Context::cancelled(); a second one ends the process at once (exit 130).
#pragma once

#include <atomic>

namespace lista::core {

std::atomic<bool>& cancel_flag();
void install_sigint_handler();

}  // namespace lista::core
