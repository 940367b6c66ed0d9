// libFuzzer harness: one serialised message through every CDR decoder of
// the ROS 2 bag reader (PointCloud2 whole and headers only, TFMessage,
// Odometry, PoseStamped). A lista::Error is the expected answer to bad
// bytes; a cloud that decodes must re-encode to bytes that decode the same.
#include <lista/error.hpp>

#include "cdr.hpp"

#include <cstdlib>

namespace {
template <class F>
void expect_error_or_value(F&& decode) {
  try {
    decode();
  } catch (const lista::Error&) {
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace lista::bag::cdr;
  expect_error_or_value([&] { decode_cloud(data, size, true); });
  expect_error_or_value([&] { decode_tf(data, size); });
  expect_error_or_value([&] { decode_odometry(data, size); });
  expect_error_or_value([&] { decode_pose_stamped(data, size); });
  try {
    const lista::bag::Cloud cloud = decode_cloud(data, size, false);
    const lista::bag::Cloud headers = decode_cloud(data, size, true);
    if (!headers.data.empty() || headers.fields.size() != cloud.fields.size()) std::abort();
    // Stamps come back through seconds as a double: compare what they carry.
    const std::vector<uint8_t> again = encode_cloud(cloud);
    const lista::bag::Cloud back = decode_cloud(again.data(), again.size(), false);
    if (back.data != cloud.data || back.fields.size() != cloud.fields.size() || back.frame_id != cloud.frame_id ||
        back.point_step != cloud.point_step || back.row_step != cloud.row_step)
      std::abort();
  } catch (const lista::Error&) {
  }
  return 0;
}
