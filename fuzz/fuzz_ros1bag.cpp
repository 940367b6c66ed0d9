// libFuzzer harness: one ROS 1 .bag file read as a bag mission's reader reads
// it (rosbag_storage, then our conversion of every topic it can decode). A
// lista::Error is the expected answer to bad input; anything else (a crash,
// a sanitizer report in our code, another exception) is a finding. rosbag
// itself is Debian's build, not instrumented: a fault inside it shows as a
// crash, not as a sanitizer report.
#include "fuzz_bag.hpp"
#include "fuzz_input.hpp"

#include <lista/error.hpp>
#include <lista_bag/ros1.hpp>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = lista_fuzz::scratch_file(".bag", data, size);
  try {
    lista_fuzz::read_every_topic(*lista::bag::open_ros1({path}));
  } catch (const lista::Error&) {
  }
  return 0;
}
