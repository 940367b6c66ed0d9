#include "truth.hpp"

#include <lista/error.hpp>
#include <lista_bag/bag_mission.hpp>
#include <lista_io/dataset.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>

namespace lista::eval {

bool poses_differ(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  const double dt = (a.block<3, 1>(0, 3) - b.block<3, 1>(0, 3)).norm();
  const Eigen::Matrix3d r = a.block<3, 3>(0, 0).transpose() * b.block<3, 3>(0, 0);
  const double angle = Eigen::AngleAxisd(r).angle() * 180.0 / M_PI;
  return dt > kMovedMeters || angle > kMovedDegrees;
}

const io::TruthObject* Truth::object(uint32_t id) const {
  for (const auto& o : gt.objects)
    if (uint32_t(o.id) == id) return &o;
  return nullptr;
}

size_t Truth::mission_index(const std::string& name) const {
  for (size_t k = 0; k < missions.missions.size(); ++k)
    if (missions.missions[k].name == name) return k;
  throw Error("mission '" + name + "' is not in the dataset's compared missions");
}

Truth load_truth(const std::string& dataset, const std::vector<std::string>& wanted, int threads) {
  Truth t;
  t.dataset = dataset;
  const std::string gt_path = (std::filesystem::path(dataset) / "ground_truth.json").string();
  if (!std::filesystem::exists(gt_path)) throw Error(gt_path + ": no ground truth; cannot score this dataset");
  t.gt = io::read_ground_truth(gt_path);
  std::vector<std::string> names = wanted.empty() ? t.gt.missions : wanted;
  for (const auto& n : names)
    if (std::find(t.gt.missions.begin(), t.gt.missions.end(), n) == t.gt.missions.end())
      throw Error("mission '" + n + "' is not in " + gt_path);
  io::DatasetOptions opt;
  opt.missions = names;
  opt.threads = threads;
  // Bag missions with what their bags and mission.toml say (io.missions' defaults).
  opt.read_bag_mission = [](const std::string& dir, const io::DatasetOptions& o) {
    return bag::read_bag_mission(dir, o, bag::BagOptions{});
  };
  t.missions = io::read_dataset(dataset, opt);

  for (const auto& m : t.missions.missions) {
    MissionTruth mt;
    mt.name = m.name;
    mt.labels.resize(m.scans.size());
    for (size_t s = 0; s < m.scans.size(); ++s) {
      const PointSet& p = *m.scans[s].points;
      if (!p.empty() && !p.has_label())
        throw Error(m.scans[s].file + ": no 'label' field (or labels that are not uint32 object ids, such as -1 or 1.5); the dataset cannot be "
                    "scored per point");
      auto& l = mt.labels[s];
      l.assign(m.scans[s].points_in_file, kNoPoint);
      for (size_t i = 0; i < p.size(); ++i) {
        l[p.index[i]] = p.label[i];
        ++mt.points_per_label[p.label[i]];
      }
    }
    t.labels.push_back(std::move(mt));
  }

  // Which objects changed between the compared missions, and how, per mission.
  for (const auto& o : t.gt.objects) {
    const uint32_t id = uint32_t(o.id);
    if (o.dynamic) {
      t.dynamic.insert(id);
      continue;
    }
    std::vector<const Eigen::Matrix4d*> pose;
    for (const auto& n : names) {
      auto it = o.poses.find(n);
      pose.push_back(it != o.poses.end() && it->second ? &*it->second : nullptr);
    }
    for (size_t k = 0; k < names.size(); ++k) {
      if (!pose[k]) continue;
      bool later_absent = false, earlier_absent = false, moved = false;
      for (size_t j = 0; j < names.size(); ++j) {
        if (j == k) continue;
        if (!pose[j]) (j > k ? later_absent : earlier_absent) = true;
        else if (poses_differ(*pose[k], *pose[j])) moved = true;
      }
      // Removed wins over added, added over moved (exact for two missions).
      const char* s = later_absent ? "removed" : earlier_absent ? "added" : moved ? "moved" : nullptr;
      if (!s) continue;
      std::set<std::string> by_neighbours;
      if (k + 1 < names.size()) {
        if (!pose[k + 1]) by_neighbours.insert("removed");
        else if (poses_differ(*pose[k], *pose[k + 1])) by_neighbours.insert("moved");
      }
      if (k > 0) {
        if (!pose[k - 1]) by_neighbours.insert("added");
        else if (poses_differ(*pose[k], *pose[k - 1])) by_neighbours.insert("moved");
      }
      if (by_neighbours.empty()) by_neighbours.insert(s);
      for (const char* first : {"moved", "removed", "added"})
        if (by_neighbours.count(first)) {
          s = first;
          break;
        }
      t.status[id][names[k]] = s;
      t.accepted[id][names[k]] = std::move(by_neighbours);
      t.changed.insert(id);
    }
  }
  // Swaps: a moved object and another of its class, both present in two
  // compared missions, each standing in the second where the other stood
  // in the first.
  auto near = [](const Eigen::Matrix4d& x, const Eigen::Matrix4d& y) {
    return (x.block<3, 1>(0, 3) - y.block<3, 1>(0, 3)).norm() <= kSwapMeters;
  };
  for (size_t k = 0; k < names.size(); ++k)
    for (size_t j = 0; j < names.size(); ++j) {
      if (j == k) continue;
      for (const auto& a : t.gt.objects) {
        const uint32_t id = uint32_t(a.id);
        if (a.dynamic || !t.status.count(id) || !t.status.at(id).count(names[k])) continue;
        const auto pa_k = a.poses.find(names[k]), pa_j = a.poses.find(names[j]);
        if (pa_k == a.poses.end() || !pa_k->second || pa_j == a.poses.end() || !pa_j->second) continue;
        for (const auto& b : t.gt.objects) {
          if (b.id == a.id || b.dynamic || b.class_name != a.class_name) continue;
          const auto pb_k = b.poses.find(names[k]), pb_j = b.poses.find(names[j]);
          if (pb_k == b.poses.end() || !pb_k->second || pb_j == b.poses.end() || !pb_j->second) continue;
          if (near(*pa_j->second, *pb_k->second) && near(*pb_j->second, *pa_k->second)) {
            t.swapped[names[k]].insert(id);
            break;
          }
        }
      }
    }
  return t;
}

}  // namespace lista::eval
