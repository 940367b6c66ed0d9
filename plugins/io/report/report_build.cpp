#include "report_build.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include <map>
#include <set>
#include <unordered_set>

namespace lista::io {

namespace {

uint64_t key(uint32_t scan, uint32_t index) { return (uint64_t(scan) << 32) | index; }

}  // namespace

void ChangeCloud::push_back(const Eigen::Vector3f& p, uint32_t s, uint32_t i, int32_t o) {
  x.push_back(p.x());
  y.push_back(p.y());
  z.push_back(p.z());
  scan.push_back(s);
  index.push_back(i);
  object.push_back(o);
}

void ChangeCloud::append(const ChangeCloud& o) {
  x.insert(x.end(), o.x.begin(), o.x.end());
  y.insert(y.end(), o.y.begin(), o.y.end());
  z.insert(z.end(), o.z.begin(), o.z.end());
  scan.insert(scan.end(), o.scan.begin(), o.scan.end());
  index.insert(index.end(), o.index.begin(), o.index.end());
  object.insert(object.end(), o.object.begin(), o.object.end());
}

Built build_report(const MissionSet& missions, const ObjectSet& objects, const Groups* groups,
                   const Matches* matches, const MissionPoints* changes) {
  Built b;
  io::Report& r = b.report;
  // Stages work near zero (MissionSet::origin); the report is in the
  // dataset's own coordinates: positions + origin, frame maps conjugated.
  const Eigen::Vector3d origin = missions.origin;
  auto restore = [&](const Eigen::Matrix4d& local) {
    Eigen::Matrix4d shift = Eigen::Matrix4d::Identity(), back = Eigen::Matrix4d::Identity();
    shift.block<3, 1>(0, 3) = origin;
    back.block<3, 1>(0, 3) = -origin;
    return Eigen::Matrix4d(shift * local * back);
  };
  auto push_point = [&](ChangeCloud& c, const Eigen::Vector3f& p, uint32_t scan, uint32_t index, int32_t object) {
    c.push_back((p.cast<double>() + origin).cast<float>(), scan, index, object);
  };
  std::map<std::string, size_t> mission_index;
  for (const auto& m : missions.missions) {
    mission_index[m.name] = r.missions.size();
    r.missions.push_back(m.name);
    r.alignment[m.name] = restore(m.to_common.matrix());
    b.clouds.push_back({m.name, {}, {}, {}, {}, {}, {}});
    ScanPoses sp{m.name, {}};
    for (size_t i = 0; i < m.scans.size(); ++i) {
      io::PoseRecord pr;
      pr.timestamp = m.scans[i].timestamp;
      pr.pose = m.sensor_to_common(i);
      pr.pose.translation() += origin;
      sp.poses.push_back(pr);
    }
    b.poses.push_back(std::move(sp));
  }
  auto cloud_of = [&](const std::string& name, const char* what) -> ChangeCloud& {
    auto it = mission_index.find(name);
    if (it == mission_index.end())
      throw Error(std::string(what) + " names mission '" + name + "', which the missions input lacks");
    return b.clouds[it->second];
  };

  std::set<int> ids;
  std::vector<std::unordered_set<uint64_t>> taken(b.clouds.size());
  size_t fallback = 0;
  for (const Object& o : objects.objects) {
    if (o.mission >= objects.missions.size())
      throw Error("object " + std::to_string(o.id) + " has mission index " + std::to_string(o.mission) +
                  " out of range");
    if (!ids.insert(o.id).second) throw Error("object id " + std::to_string(o.id) + " is not unique");
    io::ReportObject ro;
    ro.id = o.id;
    ro.mission = objects.missions[o.mission];
    ChangeCloud& cloud = cloud_of(ro.mission, "objects input");
    Eigen::Vector3f lo, hi;
    o.points.bounds(lo, hi);
    ro.centroid = (o.points.empty() ? o.centroid.cast<double>() : o.points.centroid().cast<double>()) + origin;
    ro.bbox_min = (o.points.empty() ? o.bbox_min.cast<double>() : lo.cast<double>()) + origin;
    ro.bbox_max = (o.points.empty() ? o.bbox_max.cast<double>() : hi.cast<double>()) + origin;
    ro.points = o.points.size();
    if (std::isfinite(o.floor_z)) ro.floor_z = double(o.floor_z) + origin.z();
    ro.group = groups ? groups->group_of(o.id) : -1;
    const ObjectChange* c = matches ? matches->find(o.id) : nullptr;
    if (c) {
      ro.status = to_string(c->status);
      ro.confidence = std::min(1.0, std::max(0.0, c->confidence));
      ro.history = c->history;
      if (c->status == ChangeStatus::moved) {
        const Object* partner = objects.find(c->match);
        if (!partner)
          throw Error("object " + std::to_string(o.id) + " is 'moved' but its match " + std::to_string(c->match) +
                      " is not among the objects");
        ro.match = c->match;
        if (c->has_transform) {
          ro.transform = restore(c->transform);
          for (const Eigen::Matrix4d& a : c->alternative_transforms) ro.alternative_transforms.push_back(restore(a));
        } else {
          Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
          t.block<3, 1>(0, 3) = (partner->points.centroid() - o.points.centroid()).cast<double>();
          ro.transform = t;  // a translation: the same in every frame
          b.warnings.push_back("object " + std::to_string(o.id) +
                               " is moved without a transform; wrote the centroid translation");
        }
      }
    } else {
      // No decision for this object: the mission-order rule (documented).
      ++fallback;
      ro.status = o.mission == 0 ? "removed" : "added";
      ro.confidence = 0.5;
      ro.history = {o.id};
    }
    if (!c && groups) {
      for (size_t k = 0; k < groups->object_ids.size(); ++k)
        if (groups->object_ids[k] == o.id && k < groups->confidence.size())
          ro.confidence = std::min(1.0, std::max(0.0, groups->confidence[k]));
    }
    for (size_t i = 0; i < o.points.size(); ++i) {
      const uint32_t s = o.points.scan.at(i), idx = o.points.index.at(i);
      if (taken[&cloud - b.clouds.data()].insert(key(s, idx)).second) push_point(cloud, o.points.xyz[i], s, idx, o.id);
    }
    r.objects.push_back(std::move(ro));
  }
  if (matches && fallback > 0)
    b.warnings.push_back(std::to_string(fallback) +
                         " objects have no entry in the matches; their status follows mission order");
  if (changes) {
    if (changes->sets.size() != changes->missions.size())
      throw Error("changes input has " + std::to_string(changes->sets.size()) + " point sets for " +
                  std::to_string(changes->missions.size()) + " missions");
    for (size_t k = 0; k < changes->sets.size(); ++k) {
      ChangeCloud& cloud = cloud_of(changes->missions[k], "changes input");
      auto& seen = taken[&cloud - b.clouds.data()];
      const PointSet& p = changes->sets[k];
      p.check_consistent();
      for (size_t i = 0; i < p.size(); ++i)
        if (seen.insert(key(p.scan[i], p.index[i])).second) push_point(cloud, p.xyz[i], p.scan[i], p.index[i], -1);
    }
  }
  return b;
}

std::string provenance_json(const RunInfo& run, const Eigen::Vector3d& local_origin, const ObjectSet& objects) {
  using json = nlohmann::ordered_json;
  json prov;
  prov["lista_version"] = run.lista_version;
  prov["git_revision"] = run.git_revision;
  prov["pipeline_file"] = run.pipeline_file;
  prov["pipeline"] = run.pipeline_resolved;
  prov["dataset"] = run.dataset;
  prov["seed"] = run.seed;
  prov["threads"] = run.threads;
  prov["jobs"] = run.jobs;
  json plugins = json::array();
  for (const auto& p : run.plugins) plugins.push_back({{"name", p.name}, {"version", p.version}, {"library", p.library}});
  prov["plugins"] = plugins;
  json stages = json::array();
  for (const auto& s : run.finished)
    stages.push_back({{"id", s.id}, {"plugin", s.plugin}, {"seconds", s.seconds},
                      {"peak_rss_mib", double(s.peak_rss_bytes) / (1024.0 * 1024.0)}});
  prov["stages"] = stages;
  json notes = json::object();
  for (const auto& [stage, texts] : run.notes) notes[stage] = texts;
  prov["notes"] = notes;
  json metrics = json::object();
  for (const auto& [stage, values] : run.metrics) {
    json m = json::object();
    for (const auto& [k, v] : values) m[k] = v;
    metrics[stage] = m;
  }
  json root;
  // Where the run's local frame (changes.ply, report.html's maps) lies in the
  // dataset's coordinates; report.json and changes/ have it added back already.
  root["local_origin"] = {local_origin.x(), local_origin.y(), local_origin.z()};
  root["provenance"] = prov;
  root["metrics"] = metrics;
  root["warnings"] = run.warnings;
  json dynamics = json::array();
  auto at = [&](const Eigen::Vector3f& p) {
    const Eigen::Vector3d q = p.cast<double>() + local_origin;
    return json::array({q.x(), q.y(), q.z()});
  };
  for (const Dynamic& d : objects.dynamics)
    dynamics.push_back({{"mission", d.mission < objects.missions.size() ? objects.missions[d.mission] : ""},
                        {"centroid", at(d.centroid)},
                        {"bbox_min", at(d.bbox_min)},
                        {"bbox_max", at(d.bbox_max)},
                        {"points", d.points}});
  root["dynamics"] = dynamics;
  return root.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace lista::io
