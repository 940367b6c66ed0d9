#include <lista_raycast/memory_budget.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>

namespace lista::raycast {

namespace {

// The first number after `key` in /proc/meminfo, in bytes; 0 if absent.
uint64_t meminfo(const std::string& key) {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      std::istringstream s(line.substr(key.size()));
      uint64_t kib = 0;
      s >> kib;
      return kib * 1024;
    }
  return 0;
}

// This process's virtual size and data segment (VmSize, VmData), bytes.
void process_size(uint64_t& virtual_bytes, uint64_t& data_bytes) {
  std::ifstream in("/proc/self/status");
  std::string line;
  virtual_bytes = data_bytes = 0;
  while (std::getline(in, line)) {
    std::istringstream s(line.substr(line.find(':') + 1));
    uint64_t kib = 0;
    s >> kib;
    if (line.rfind("VmSize:", 0) == 0) virtual_bytes = kib * 1024;
    if (line.rfind("VmData:", 0) == 0) data_bytes = kib * 1024;
  }
}

uint64_t read_number(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return std::numeric_limits<uint64_t>::max();
  try {
    return std::stoull(text);
  } catch (...) {
    return std::numeric_limits<uint64_t>::max();
  }
}

}  // namespace

uint64_t memory_available_bytes() {
  uint64_t avail = meminfo("MemAvailable:");
  if (avail == 0) avail = std::numeric_limits<uint64_t>::max();
  uint64_t vsize = 0, data = 0;
  process_size(vsize, data);
  auto less_used = [](uint64_t limit, uint64_t used) { return limit > used ? limit - used : 0; };
  rlimit r{};
  if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY) avail = std::min(avail, less_used(r.rlim_cur, vsize));
  if (getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY) avail = std::min(avail, less_used(r.rlim_cur, data));
  const uint64_t cg_max = read_number("/sys/fs/cgroup/memory.max");
  if (cg_max != std::numeric_limits<uint64_t>::max())
    avail = std::min(avail, less_used(cg_max, read_number("/sys/fs/cgroup/memory.current")));
  return avail;
}

}  // namespace lista::raycast
