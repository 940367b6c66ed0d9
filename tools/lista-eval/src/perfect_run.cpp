#include "perfect_run.hpp"

#include <lista/error.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>

#include <filesystem>
#include <map>
#include <set>

namespace fs = std::filesystem;

namespace lista::eval {

namespace {
Eigen::Isometry3d iso(const Eigen::Matrix4d& m) {
  Eigen::Isometry3d t;
  t.matrix() = m;
  return t;
}
}  // namespace

void write_perfect_run(const Truth& truth, const std::string& out_dir) {
  std::error_code ec;
  fs::create_directories(fs::path(out_dir) / "changes", ec);
  if (ec) throw Error(out_dir + ": cannot create the output folder (" + ec.message() + ")");
  fs::remove(fs::path(out_dir) / "report.json", ec);
  const size_t nm = truth.missions.missions.size();

  // Report ids: per changed object, per mission it is seen in.
  std::map<std::pair<uint32_t, size_t>, int> rid;
  std::set<std::string> classes;
  int next = 0;
  for (const auto& o : truth.gt.objects) {
    const uint32_t id = uint32_t(o.id);
    if (!truth.changed.count(id)) continue;
    classes.insert(o.class_name);
    for (size_t k = 0; k < nm; ++k)
      if (truth.status.at(id).count(truth.labels[k].name) && truth.labels[k].points_per_label.count(id))
        rid[{id, k}] = next++;
  }
  std::map<std::string, int> group;
  for (const auto& c : classes) group[c] = int(group.size());

  io::Report report;
  for (const auto& m : truth.missions.missions) {
    report.missions.push_back(m.name);
    report.alignment[m.name] = truth.gt.mission_to_world.at(m.name);
  }
  std::map<int, io::ReportObject> objects;
  std::map<int, Eigen::Vector3d> sum;
  for (size_t k = 0; k < nm; ++k) {
    const Mission& m = truth.missions.missions[k];
    const Eigen::Isometry3d to_world = iso(truth.gt.mission_to_world.at(m.name));
    std::vector<float> x, y, z;
    std::vector<uint32_t> scan, index;
    std::vector<int32_t> object;
    for (size_t s = 0; s < m.scans.size(); ++s) {
      // True sensor pose when known, so the points sit where the objects really are.
      const Eigen::Isometry3f pose =
          (m.poses_gt.empty() ? to_world * m.scans[s].pose : m.poses_gt[s]).cast<float>();
      const PointSet& p = *m.scans[s].points;
      for (size_t i = 0; i < p.size(); ++i) {
        auto it = rid.find({p.label[i], k});
        if (it == rid.end()) continue;
        const Eigen::Vector3f w = pose * p.xyz[i];
        x.push_back(w.x());
        y.push_back(w.y());
        z.push_back(w.z());
        scan.push_back(uint32_t(s));
        index.push_back(p.index[i]);
        object.push_back(it->second);
        io::ReportObject& o = objects[it->second];
        const Eigen::Vector3d wd = w.cast<double>();
        if (o.points == 0) {
          o.bbox_min = o.bbox_max = wd;
          sum[it->second] = Eigen::Vector3d::Zero();
        }
        o.bbox_min = o.bbox_min.cwiseMin(wd);
        o.bbox_max = o.bbox_max.cwiseMax(wd);
        sum[it->second] += wd;
        ++o.points;
      }
    }
    io::write_pcd((fs::path(out_dir) / "changes" / (m.name + ".pcd")).string(), x.size(),
                  {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()}, {"scan", 'U', scan.data()},
                   {"index", 'U', index.data()}, {"object", 'I', object.data()}});
  }
  for (const auto& [key, id] : rid) {
    const auto [true_id, k] = key;
    const io::TruthObject& t = *truth.object(true_id);
    const std::string& m = truth.labels[k].name;
    io::ReportObject& o = objects[id];
    o.id = id;
    o.mission = m;
    o.status = truth.status.at(true_id).at(m);
    o.centroid = sum[id] / double(o.points);
    o.group = group.at(t.class_name);
    o.confidence = 1.0;
    for (size_t j = 0; j < nm; ++j)
      if (rid.count({true_id, j})) o.history.push_back(rid.at({true_id, j}));
    if (o.status == "moved") {
      // Partner: the nearest mission, later ones first, where it is seen
      // in another pose (with 3+ missions it may stand still in between).
      auto moved_in = [&](size_t j) {
        const auto& pose = t.poses.at(truth.labels[j].name);
        return rid.count({true_id, j}) && pose && poses_differ(*pose, *t.poses.at(m));
      };
      long partner = -1;
      for (size_t j = k + 1; j < nm && partner < 0; ++j)
        if (moved_in(j)) partner = long(j);
      for (long j = long(k) - 1; j >= 0 && partner < 0; --j)
        if (moved_in(size_t(j))) partner = j;
      if (partner >= 0) {
        const std::string& pm = truth.labels[size_t(partner)].name;
        o.match = rid.at({true_id, size_t(partner)});
        o.transform = (iso(*t.poses.at(pm)) * iso(*t.poses.at(m)).inverse()).matrix();
      } else {
        // Seen in one mission only: no partner to name; the transform to its
        // pose in the nearest other mission it exists in.
        for (size_t j = 0; j < nm && !o.transform; ++j) {
          const std::string& pm = truth.labels[j].name;
          if (j != k && t.poses.at(pm)) o.transform = (iso(*t.poses.at(pm)) * iso(*t.poses.at(m)).inverse()).matrix();
        }
      }
    }
  }
  for (auto& [id, o] : objects) report.objects.push_back(o);
  report.extra_json = "{\"provenance\": {\"generator\": \"lista-eval --truth\"}}";
  // Every scan at its true pose, in the world frame the alignment maps to.
  for (const Mission& m : truth.missions.missions) {
    if (m.poses_gt.size() != m.scans.size() || m.poses_gt.empty()) continue;
    std::vector<io::PoseRecord> poses;
    for (size_t i = 0; i < m.scans.size(); ++i) poses.push_back({m.scans[i].timestamp, m.poses_gt[i]});
    fs::create_directories(fs::path(out_dir) / "poses", ec);
    io::write_poses((fs::path(out_dir) / "poses" / (m.name + ".txt")).string(), poses);
  }
  io::write_report((fs::path(out_dir) / "report.json").string(), report);
}

}  // namespace lista::eval
