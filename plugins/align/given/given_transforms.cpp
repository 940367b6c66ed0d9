#include "given_transforms.hpp"

#include <lista/error.hpp>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace lista::align {

std::map<std::string, Eigen::Isometry3d> read_transform_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot read the transforms file");
  std::map<std::string, Eigen::Isometry3d> out;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ss(line);
    std::string name, tok;
    if (!(ss >> name)) continue;
    std::vector<double> v;
    auto fail = [&](const std::string& what) { return Error(path + ":" + std::to_string(line_no) + ": " + what); };
    while (ss >> tok) {
      char* end = nullptr;
      const double d = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size() || !std::isfinite(d)) throw fail("'" + tok + "' is not a finite number");
      v.push_back(d);
    }
    if (v.size() != 16 && v.size() != 12)
      throw fail("expected a mission name and 16 (4x4) or 12 (3x4) numbers, got " + std::to_string(v.size()));
    if (out.count(name)) throw fail("mission '" + name + "' given twice");
    Eigen::Matrix3d R;
    R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
    if (v.size() == 16 && (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1))
      throw fail("the last row of a 4x4 transform must be 0 0 0 1");
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-3 || R.determinant() < 0)
      throw fail("rotation of '" + name + "' is not orthonormal");
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = svd.matrixU() * svd.matrixV().transpose();
    T.translation() = Eigen::Vector3d(v[3], v[7], v[11]);
    out[name] = T;
  }
  return out;
}

Eigen::Isometry3d map_to_world_from_gt(const Mission& m) {
  if (m.poses_gt.empty())
    throw Error("mission '" + m.name + "' has no poses_gt.txt; modes \"ground-truth\" and \"ground-truth-poses\" need one per mission");
  if (m.poses_gt.size() != m.scans.size())
    throw Error("mission '" + m.name + "': poses_gt has " + std::to_string(m.poses_gt.size()) + " poses for " +
                std::to_string(m.scans.size()) + " scans");
  const size_t n = m.scans.size();
  Eigen::Matrix3Xd src(3, 4 * n), dst(3, 4 * n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Isometry3d& P = m.scans[i].pose;
    const Eigen::Isometry3d& G = m.poses_gt[i];
    src.col(4 * i) = P.translation();
    dst.col(4 * i) = G.translation();
    for (int k = 0; k < 3; ++k) {
      src.col(4 * i + 1 + k) = P * Eigen::Vector3d::Unit(k);
      dst.col(4 * i + 1 + k) = G * Eigen::Vector3d::Unit(k);
    }
  }
  Eigen::Isometry3d T;
  T.matrix() = Eigen::umeyama(src, dst, false);
  return T;
}

}  // namespace lista::align
