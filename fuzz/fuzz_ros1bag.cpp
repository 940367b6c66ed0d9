// libFuzzer harness: one ROS 1 .bag file read as a bag mission's reader reads
// it (rosbag_storage, then our conversion of every topic it can decode). A
// lista::Error is the expected answer to bad input; anything else (a crash,
// a sanitizer report in our code, another exception) is a finding. rosbag
// itself is Debian's build, not instrumented: a fault inside it shows as a
// crash, not as a sanitizer report.
#include "fuzz_input.hpp"

#include <lista/error.hpp>
#include <lista_bag/ros1.hpp>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = lista_fuzz::scratch_file(".bag", data, size);
  try {
    auto reader = lista::bag::open_ros1({path});
    std::vector<std::string> topics;
    for (const lista::bag::TopicInfo& t : reader->topics())
      if (t.kind != lista::bag::MessageKind::other) topics.push_back(t.name);
    lista::bag::Visitor visitor;
    visitor.cloud = [](const std::string&, lista::bag::Cloud&&) {};
    visitor.tf = [](const std::string&, std::vector<lista::bag::FrameTransform>&&, bool) {};
    visitor.pose = [](const std::string&, lista::bag::StampedPose&&) {};
    for (bool headers_only : {false, true}) reader->read(topics, visitor, headers_only);
  } catch (const lista::Error&) {
  }
  return 0;
}
