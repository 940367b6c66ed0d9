#include "bag_writer.hpp"

#include <lista_bag/ros1.hpp>
#include <lista_bag/ros2.hpp>

#include <cstring>
#include <filesystem>

namespace lista::sim {

namespace {

bag::Cloud to_cloud(double stamp, const PointSet& p, const std::vector<float>& times) {
  bag::Cloud c;
  c.stamp = stamp;
  c.frame_id = kBagSensorFrame;
  c.height = 1;
  c.width = uint32_t(p.size());
  c.fields = {{"x", 0, bag::float32, 1}, {"y", 4, bag::float32, 1}, {"z", 8, bag::float32, 1}};
  uint32_t step = 12;
  if (p.has_intensity()) c.fields.push_back({"intensity", step, bag::float32, 1}), step += 4;
  if (p.has_label()) c.fields.push_back({"label", step, bag::uint32, 1}), step += 4;
  if (!times.empty()) c.fields.push_back({"time", step, bag::float32, 1}), step += 4;
  c.point_step = step;
  c.row_step = step * c.width;
  c.is_dense = true;
  c.data.resize(size_t(c.row_step));
  for (size_t i = 0; i < p.size(); ++i) {
    uint8_t* out = c.data.data() + i * step;
    std::memcpy(out, p.xyz[i].data(), 12);
    size_t at = 12;
    if (p.has_intensity()) std::memcpy(out + at, &p.intensity[i], 4), at += 4;
    if (p.has_label()) std::memcpy(out + at, &p.label[i], 4), at += 4;
    if (!times.empty()) std::memcpy(out + at, &times[i], 4);
  }
  return c;
}

}  // namespace

// The LiDAR at the base's origin: a pose the reader composes from the base's
// and the mount's is then bit for bit the sensor pose the folders carry, so
// a bag run can be compared with a folder run exactly (a rotated mount is
// tested in common/bag/tests).
Eigen::Isometry3d MissionBagWriter::mount() { return Eigen::Isometry3d::Identity(); }

MissionBagWriter::MissionBagWriter(const std::string& mission_dir, BagFormat format) {
  std::filesystem::create_directories(mission_dir);
  const std::filesystem::path dir(mission_dir);
  if (format == BagFormat::ros1)
    writer_ = bag::create_ros1((dir / "mission.bag").string());
  else
    writer_ = bag::create_ros2((dir / "bag").string(),
                               format == BagFormat::ros2_mcap ? bag::Ros2Storage::mcap : bag::Ros2Storage::sqlite3);
  writer_->write_tf("/tf_static", {{kBagStartTime, "map", "odom", Eigen::Isometry3d::Identity()},
                                   {kBagStartTime, "base_link", kBagSensorFrame, mount()}},
                    kBagStartTime);
}

void MissionBagWriter::add(double stamp, const PointSet& points, const std::vector<float>& times,
                           const Eigen::Isometry3d& sensor_pose) {
  add_pose(stamp, sensor_pose);
  writer_->write_cloud(kBagCloudTopic, to_cloud(stamp, points, times), stamp);
}

void MissionBagWriter::add_pose(double stamp, const Eigen::Isometry3d& sensor_pose) {
  // The robot's odometry gives the base; the sensor hangs under it by mount().
  const Eigen::Isometry3d base = sensor_pose * mount().inverse();
  writer_->write_tf("/tf", {{stamp, "odom", "base_link", base}}, stamp);
  writer_->write_odometry(kBagOdometryTopic, {stamp, "odom", "base_link", base}, stamp);
}

void MissionBagWriter::close() {
  writer_->close();
}

}  // namespace lista::sim
