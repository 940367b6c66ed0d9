// libFuzzer harness: one .mcap file opened as a ROS 2 bag and every topic
// read (clouds whole, then headers only). A lista::Error is the expected
// answer to bad input; anything else (a crash, a sanitizer report, another
// exception) is a finding.
#include "fuzz_bag.hpp"
#include "fuzz_input.hpp"

#include <lista/error.hpp>
#include <lista_bag/ros2.hpp>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = lista_fuzz::scratch_file(".mcap", data, size);
  try {
    lista_fuzz::read_every_topic(*lista::bag::open_ros2(path));
  } catch (const lista::Error&) {
  }
  return 0;
}
