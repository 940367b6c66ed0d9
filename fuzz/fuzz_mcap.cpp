// libFuzzer harness: one .mcap file opened as a ROS 2 bag and every topic
// read (clouds whole, then headers only). A lista::Error is the expected
// answer to bad input; anything else (a crash, a sanitizer report, another
// exception) is a finding.
#include "fuzz_input.hpp"

#include <lista/error.hpp>
#include <lista_bag/ros2.hpp>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = lista_fuzz::scratch_file(".mcap", data, size);
  try {
    auto reader = lista::bag::open_ros2(path);
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
