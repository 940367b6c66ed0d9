#include "truth_score.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <map>

namespace {

bool differs(const std::optional<Eigen::Matrix4d>& a, const std::optional<Eigen::Matrix4d>& b) {
  if (!a || !b) return a.has_value() != b.has_value();
  const Eigen::Matrix4d d = a->inverse() * *b;
  const double t = d.block<3, 1>(0, 3).norm();
  const double cosang = std::clamp((d.block<3, 3>(0, 0).trace() - 1.0) / 2.0, -1.0, 1.0);
  return t > 0.05 || std::acos(cosang) > 5.0 * M_PI / 180.0;
}

}  // namespace

PointScore score_points(const lista::MissionSet& missions, const lista::io::GroundTruth& truth,
                        const std::vector<std::set<std::pair<uint32_t, uint32_t>>>& changed) {
  PointScore s;
  const size_t n = missions.missions.size();
  for (size_t m = 0; m < n; ++m) {
    std::map<uint32_t, bool> label_changed;  // object id -> changed vs a neighbour
    std::set<uint32_t> dynamic;
    for (const auto& o : truth.objects) {
      if (o.dynamic) dynamic.insert(static_cast<uint32_t>(o.id));
      auto pose = [&](size_t k) {
        auto it = o.poses.find(missions.missions[k].name);
        return it == o.poses.end() ? std::optional<Eigen::Matrix4d>() : it->second;
      };
      bool c = false;
      if (m > 0) c = c || differs(pose(m - 1), pose(m));
      if (m + 1 < n) c = c || differs(pose(m), pose(m + 1));
      label_changed[static_cast<uint32_t>(o.id)] = c;
    }
    const auto& mission = missions.missions[m];
    for (size_t i = 0; i < mission.scans.size(); ++i) {
      const lista::PointSet& p = *mission.scans[i].points;
      for (size_t j = 0; j < p.size(); ++j) {
        const uint32_t label = p.has_label() ? p.label[j] : 0;
        if (dynamic.count(label)) continue;
        const auto it = label_changed.find(label);
        const bool truly = label != 0 && it != label_changed.end() && it->second;
        const bool pred = changed[m].count({static_cast<uint32_t>(i), p.index.empty() ? uint32_t(j) : p.index[j]}) != 0;
        if (truly && pred) ++s.tp;
        else if (truly) ++s.fn;
        else if (pred) ++s.fp;
        else ++s.tn;
      }
    }
  }
  return s;
}
