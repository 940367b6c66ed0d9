// Death-test helpers for stages that must stop cleanly when memory runs
// out (header only): cap the address space a little above what the process
// maps now, run the stage, and report how it ended as an exit code.
#pragma once

#include <lista/error.hpp>

#include <sys/resource.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

namespace test_support {

// Caps the address space `headroom` bytes above the process's VmSize.
inline void cap_address_space(rlim_t headroom) {
  std::ifstream status("/proc/self/status");
  std::string line;
  rlim_t used = 0;
  while (std::getline(status, line))
    if (line.rfind("VmSize:", 0) == 0) used = rlim_t(std::stoull(line.substr(7))) * 1024;
  const rlimit cap{used + headroom, used + headroom};
  setrlimit(RLIMIT_AS, &cap);
}

// Runs `body`; exits 3 with a lista::Error's message on stderr, 0 if it
// threw none (anything else ends the process as it would).
template <class Body>
[[noreturn]] void exit_3_on_error(Body body) {
  try {
    body();
  } catch (const lista::Error& e) {
    std::cerr << e.what() << "\n";
    std::_Exit(3);
  }
  std::_Exit(0);
}

}  // namespace test_support
