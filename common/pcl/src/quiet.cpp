#include <lista_pcl/quiet.hpp>

#include <mutex>

namespace lista::pcl_convert {

namespace {
std::mutex mutex;
int holders = 0;
pcl::console::VERBOSITY_LEVEL before = pcl::console::L_INFO;
}  // namespace

QuietPcl::QuietPcl() {
  std::lock_guard<std::mutex> lock(mutex);
  if (holders++ == 0) {
    before = pcl::console::getVerbosityLevel();
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
}

QuietPcl::~QuietPcl() {
  std::lock_guard<std::mutex> lock(mutex);
  if (--holders == 0) pcl::console::setVerbosityLevel(before);
}

}  // namespace lista::pcl_convert
