#include "dataset_writer.hpp"

#include "raycaster.hpp"
#include "rng.hpp"
#include "scanner.hpp"

#include <lista/error.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>
#include <lista_io/report.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace lista::sim {
namespace fs = std::filesystem;

namespace {

void prepare_output(const Scenario& sc, const WriteOptions& opt) {
  if (opt.out.empty()) throw Error("lista-sim: --out is required");
  fs::create_directories(opt.out);
  std::vector<fs::path> ours = {fs::path(opt.out) / "ground_truth.json"};
  for (const auto& m : sc.missions) ours.push_back(fs::path(opt.out) / m.name);
  for (const auto& p : ours) {
    if (!fs::exists(p)) continue;
    if (!opt.overwrite)
      throw Error("lista-sim: " + p.string() + " already exists (pass --overwrite to replace it)");
    fs::remove_all(p);
  }
  // A previous run with more missions would leave extra mission folders.
  for (char c = char('A' + sc.missions.size()); c <= 'Z'; ++c) {
    const fs::path extra = fs::path(opt.out) / std::string(1, c);
    if (fs::exists(extra / "poses.txt") || fs::exists(extra / "mission.bag") || fs::exists(extra / "bag")) {
      if (!opt.overwrite) throw Error("lista-sim: " + extra.string() + " is left from another dataset (pass --overwrite)");
      fs::remove_all(extra);
    }
  }
}

void build_static_scene(const Scenario& sc, const MissionPlan& m, RayScene& scene) {
  for (const auto& part : sc.layout.structure) scene.add(part.mesh, Eigen::Isometry3f::Identity(), 0, part.reflectivity);
  for (const auto& [id, pose] : m.objects) {
    const Shape& s = sc.shapes[size_t(sc.object_shape.at(id))];
    scene.add(s.mesh, pose.cast<float>(), id, s.reflectivity);
  }
  scene.commit();
}

io::GroundTruth ground_truth(const Scenario& sc) {
  io::GroundTruth gt;
  for (const auto& m : sc.missions) {
    gt.missions.push_back(m.name);
    gt.mission_to_world[m.name] = m.map_to_world.matrix();
  }
  for (const auto& [id, shape] : sc.object_shape) {
    io::TruthObject o;
    o.id = int(id);
    o.class_name = sc.shapes[size_t(shape)].cls;
    for (const auto& m : sc.missions) {
      o.poses[m.name] = std::nullopt;
      const auto it = m.objects.find(id);
      if (it != m.objects.end()) o.poses[m.name] = it->second.matrix();
      for (const auto& p : m.people)
        if (p.id == id) {
          o.dynamic = true;
          o.poses[m.name] = m.person_pose(p, 0).matrix();  // where the person was at the first scan
        }
    }
    gt.objects.push_back(std::move(o));
  }
  return gt;
}

}  // namespace

WriteStats write_dataset(const Scenario& sc, const SensorModel& sensor, const WriteOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  prepare_output(sc, opt);
  WriteStats stats;
  for (size_t mi = 0; mi < sc.missions.size(); ++mi) {
    const MissionPlan& m = sc.missions[mi];
    const fs::path dir = fs::path(opt.out) / m.name;
    fs::create_directories(opt.bag ? dir : dir / "scans");
    std::optional<MissionBagWriter> bag;
    if (opt.bag) bag.emplace(dir.string(), *opt.bag);
    RayScene scene;
    build_static_scene(sc, m, scene);
    size_t points = 0;
    std::vector<io::PoseRecord> estimated, truth;
    for (size_t i = 0; i < m.poses_true.size(); ++i) {
      // People move between sweeps: a small scene of their own per scan.
      RayScene people;
      for (const auto& p : m.people) {
        const Shape& s = sc.shapes[size_t(p.shape)];
        people.add(s.mesh, m.person_pose(p, i).cast<float>(), p.id, s.reflectivity);
      }
      people.commit();
      SweepOptions so;
      so.key = hash_combine(hash_combine(opt.seed, mi + 1), i + 1);
      so.threads = opt.threads;
      so.scan_id = uint32_t(i);
      so.body = opt.body;
      so.mixed_pixels = opt.mixed_pixels;
      so.dark_dropouts = opt.dark_dropouts;
      // A skewed sweep ends where the next one starts (the last one goes on
      // as the step before it did).
      Eigen::Isometry3d sweep_end = m.poses_true[i];
      if (i + 1 < m.poses_true.size()) sweep_end = m.poses_true[i + 1];
      else if (i > 0) sweep_end = m.poses_true[i] * (m.poses_true[i - 1].inverse() * m.poses_true[i]);
      std::vector<float> times;
      if (opt.skew) so.sweep_end = &sweep_end, so.times = &times;
      const PointSet cloud = sweep(scene, people.empty() ? nullptr : &people, sensor, m.poses_true[i], so);
      const double stamp = (opt.bag ? kBagStartTime : 0.0) + 0.1 * double(i);  // 10 Hz, the sensors' rate
      if (bag) {
        bag->add(stamp, cloud, times, m.poses_estimated[i]);
      } else {
        char name[32];
        std::snprintf(name, sizeof(name), "%06zu.pcd", i);
        io::write_scan_pcd((dir / "scans" / name).string(), cloud, io::PcdEncoding::binary);
      }
      points += cloud.size();
      estimated.push_back({stamp, m.poses_estimated[i]});
      truth.push_back({stamp, m.poses_true[i]});
      if (opt.progress)
        std::fprintf(stderr, "\rlista-sim: mission %s scan %zu/%zu", m.name.c_str(), i + 1, m.poses_true.size());
    }
    if (opt.progress) std::fprintf(stderr, "\n");
    io::write_poses((dir / "poses_gt.txt").string(), truth, io::PoseFormat::tum);
    if (bag) {
      // The last skewed sweep ends 0.1 s after its stamp: the odometry goes
      // on that far, as a robot's would.
      const size_t n = m.poses_estimated.size();
      if (opt.skew && n >= 2)
        bag->add_pose(estimated.back().timestamp + 0.1,
                      m.poses_estimated[n - 1] * (m.poses_estimated[n - 2].inverse() * m.poses_estimated[n - 1]));
      bag->close();
      io::write_poses((dir / "trajectory.txt").string(), estimated, io::PoseFormat::tum);
    } else {
      // poses.txt last: a mission folder without it is visibly incomplete.
      io::write_poses((dir / "poses.txt").string(), estimated, io::PoseFormat::tum);
    }
    stats.points_per_mission.push_back(points);
    stats.scans_per_mission.push_back(m.poses_true.size());
  }
  io::write_ground_truth((fs::path(opt.out) / "ground_truth.json").string(), ground_truth(sc));
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace lista::sim
