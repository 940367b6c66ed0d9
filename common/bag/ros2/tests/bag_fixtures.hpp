// Shared by the ROS 2 bag tests: a scratch folder, one set of sample
// messages of every type (written through the bag Writer or straight into a
// storage), and what a full read of them hands out.
#pragma once

#include <lista/error.hpp>
#include <lista_bag/messages.hpp>

#include "storage.hpp"

#include <string>
#include <vector>

namespace lista_test {

// A fresh empty folder under TMPDIR, removed with the object.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  std::string path(const std::string& name = "") const { return name.empty() ? dir_ : dir_ + "/" + name; }

 private:
  std::string dir_;
};

lista::bag::Cloud sample_cloud(double stamp);
std::vector<lista::bag::FrameTransform> sample_tf(double stamp);
lista::bag::StampedPose sample_odometry(double stamp);
lista::bag::StampedPose sample_pose(double stamp);

// The samples, in record-time order: /tf_static, /tf, /odom, /pose, /points, /tf, /points.
constexpr int kSampleMessages = 7;
void write_samples(lista::bag::Writer& writer);
void write_samples(lista::bag::ros2::StorageWriter& writer);

struct Collected {
  std::vector<std::string> order;  // topic of each message, as handed out
  std::vector<lista::bag::Cloud> clouds;
  std::vector<std::vector<lista::bag::FrameTransform>> tfs;
  std::vector<bool> tf_static;
  std::vector<lista::bag::StampedPose> poses;
};
Collected read_all(lista::bag::Reader& reader, bool clouds_headers_only = false);
// Checks a full read of the samples (clouds with data unless headers_only).
void expect_samples(const Collected& got, bool clouds_headers_only = false);
void expect_same_cloud(const lista::bag::Cloud& a, const lista::bag::Cloud& b, bool with_data = true);
void expect_same_pose(const lista::bag::StampedPose& a, const lista::bag::StampedPose& b);
void expect_same_tf(const std::vector<lista::bag::FrameTransform>& a, const std::vector<lista::bag::FrameTransform>& b);

std::vector<uint8_t> read_bytes(const std::string& file);
void write_bytes(const std::string& file, const std::vector<uint8_t>& bytes);
// The message of the lista::Error `f` throws; fails the test when it does not.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const lista::Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace lista_test
