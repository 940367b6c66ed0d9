#include <lista_bench/truth_score.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>

namespace {

bool differs(const std::optional<Eigen::Matrix4d>& a, const std::optional<Eigen::Matrix4d>& b) {
  if (!a || !b) return a.has_value() != b.has_value();
  const Eigen::Matrix4d d = a->inverse() * *b;
  const double t = d.block<3, 1>(0, 3).norm();
  const double cosang = std::clamp((d.block<3, 3>(0, 0).trace() - 1.0) / 2.0, -1.0, 1.0);
  return t > 0.05 || std::acos(cosang) > 5.0 * M_PI / 180.0;
}

}  // namespace

std::set<uint32_t> objects_changed_between(const lista::io::GroundTruth& truth, const std::string& a,
                                           const std::string& b) {
  std::set<uint32_t> ids;
  for (const auto& o : truth.objects) {
    auto pose = [&](const std::string& mission) {
      auto it = o.poses.find(mission);
      return it == o.poses.end() ? std::optional<Eigen::Matrix4d>() : it->second;
    };
    if (!o.dynamic && differs(pose(a), pose(b))) ids.insert(static_cast<uint32_t>(o.id));
  }
  return ids;
}

std::set<uint32_t> dynamic_objects(const lista::io::GroundTruth& truth) {
  std::set<uint32_t> ids;
  for (const auto& o : truth.objects)
    if (o.dynamic) ids.insert(static_cast<uint32_t>(o.id));
  return ids;
}

PointScore score_points(const lista::MissionSet& missions, const lista::io::GroundTruth& truth,
                        const std::vector<std::set<std::pair<uint32_t, uint32_t>>>& changed) {
  PointScore s;
  const std::set<uint32_t> dynamic = dynamic_objects(truth);
  const auto& all = missions.missions;
  for (size_t m = 0; m < all.size(); ++m) {
    std::set<uint32_t> truly;
    if (m > 0) truly = objects_changed_between(truth, all[m - 1].name, all[m].name);
    if (m + 1 < all.size()) truly.merge(objects_changed_between(truth, all[m].name, all[m + 1].name));
    for (size_t i = 0; i < all[m].scans.size(); ++i) {
      const lista::PointSet& p = *all[m].scans[i].points;
      for (size_t j = 0; j < p.size(); ++j) {
        const uint32_t label = p.has_label() ? p.label[j] : 0;
        if (dynamic.count(label)) continue;
        const bool is_changed = label != 0 && truly.count(label);
        const bool pred = changed[m].count({static_cast<uint32_t>(i), p.index.empty() ? uint32_t(j) : p.index[j]}) != 0;
        if (is_changed && pred) ++s.tp;
        else if (is_changed) ++s.fn;
        else if (pred) ++s.fp;
        else ++s.tn;
      }
    }
  }
  return s;
}
