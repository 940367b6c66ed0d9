#include "change_ply.hpp"

#include "svg.hpp"

#include <cstdio>
#include <cstring>

namespace lista::report {

namespace {
template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // x86-64 and aarch64 are little endian
  out.append(bytes, sizeof(T));
}
}  // namespace

std::string change_ply(const ReportModel& model, const Eigen::Vector3d& local_origin) {
  size_t n = 0;
  for (const auto& v : model.objects) n += v.object->points.size();
  char origin[160];
  std::snprintf(origin, sizeof origin,
                "comment local_origin %.17g %.17g %.17g (add to x y z for the dataset's coordinates)\n",
                local_origin.x(), local_origin.y(), local_origin.z());
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment LiSTA change cloud: colour by status\n"
      "comment object = report.json id; mission = index into report.json missions; "
      "status 0 removed, 1 added, 2 moved\n" +
      std::string(origin) +
      "element vertex " + std::to_string(n) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property int object\nproperty int mission\nproperty uchar status\nend_header\n";
  out.reserve(out.size() + n * 24);
  for (const auto& v : model.objects) {
    const Rgb c = status_colour(to_string(v.status));
    const uint8_t status = v.status == ChangeStatus::removed ? 0 : v.status == ChangeStatus::added ? 1 : 2;
    for (const auto& p : v.object->points.xyz) {
      put(out, p.x());
      put(out, p.y());
      put(out, p.z());
      put(out, c.r);
      put(out, c.g);
      put(out, c.b);
      put(out, int32_t(v.object->id));
      put(out, int32_t(v.object->mission));
      put(out, status);
    }
  }
  return out;
}

}  // namespace lista::report
