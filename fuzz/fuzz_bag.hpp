// What the bag harnesses do with a reader that opened: every topic of a kind
// a mission uses read whole, then headers only. A lista::Error is the
// expected answer to bad input.
#pragma once

#include <lista_bag/messages.hpp>

namespace lista_fuzz {

inline void read_every_topic(lista::bag::Reader& reader) {
  std::vector<std::string> topics;
  for (const lista::bag::TopicInfo& t : reader.topics())
    if (t.kind != lista::bag::MessageKind::other) topics.push_back(t.name);
  lista::bag::Visitor visitor;
  visitor.cloud = [](const std::string&, lista::bag::Cloud&&) {};
  visitor.tf = [](const std::string&, std::vector<lista::bag::FrameTransform>&&, bool) {};
  visitor.pose = [](const std::string&, lista::bag::StampedPose&&) {};
  for (bool headers_only : {false, true}) reader.read(topics, visitor, headers_only);
}

}  // namespace lista_fuzz
