// Missions as read from a dataset (data contract, sect. 1) and as corrected by
// the alignment stage. Scan point data is immutable and shared, so that an
// alignment stage can output new poses without copying millions of points.
#pragma once

#include <Eigen/Geometry>
#include <lista/points.hpp>

#include <memory>
#include <string>
#include <vector>

namespace lista {

struct Scan {
  std::string file;        // path of the scan file it was read from
  double timestamp = 0.0;  // from TUM poses; the line number for KITTI poses
  // T_map_sensor: maps sensor-frame points into the mission's own map frame;
  // its translation is the sensor origin. Alignment may correct it.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // Points in the SENSOR frame; `scan` is this scan's index in the mission and
  // `index` the point's index in the file. Finite points only.
  std::shared_ptr<const PointSet> points;
  uint32_t points_in_file = 0;  // every point in the file, non-finite included
};

struct Mission {
  std::string name;  // folder name
  std::string dir;   // folder path
  std::vector<Scan> scans;
  // Maps the mission's map frame into the common frame (identity until aligned).
  Eigen::Isometry3d to_common = Eigen::Isometry3d::Identity();
  // True sensor poses in the world frame from poses_gt.txt; empty if absent.
  std::vector<Eigen::Isometry3d> poses_gt;
  size_t skipped_nonfinite = 0;

  // Sensor pose of scan i in the common frame.
  Eigen::Isometry3d sensor_to_common(size_t i) const { return to_common * scans[i].pose; }
  size_t point_count() const;
};

struct MissionSet {
  std::string dataset;  // dataset folder
  std::vector<Mission> missions;
  // Where the run's zero lies in the dataset's own coordinates. Georeferenced
  // poses (UTM, ENU) put points hundreds of km from zero, where float32 keeps
  // only centimetres, so io.missions moves the poses by -origin (a whole
  // number of km) and every stage works near zero; writers of coordinates
  // (io.report) add it back. Zero for data already near zero.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  const Mission* find(const std::string& name) const;
};

// One point set per mission, in the COMMON frame, with provenance: the change
// points that volumetric differencing and the filters pass along.
struct MissionPoints {
  std::vector<std::string> missions;  // names, same order as `sets`
  std::vector<PointSet> sets;
  size_t total() const;
};

}  // namespace lista
