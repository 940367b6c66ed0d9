#include "views.hpp"

#include "look_alikes.hpp"
#include "raycaster.hpp"
#include "rng.hpp"
#include "scanner.hpp"
#include "sensor.hpp"

#include <lista/error.hpp>
#include <lista_io/atomic_file.hpp>
#include <lista_io/pcd.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

namespace lista::sim {
namespace fs = std::filesystem;

namespace {

// Shape-level split: all views of a shape land in the same split, so a model
// can be tested on shapes it never saw.
std::string split_of(const std::string& shape_id) {
  const uint64_t h = mix64(hash_string(shape_id.c_str())) % 10;
  return h < 8 ? "train" : (h == 8 ? "val" : "test");
}

// The shapes to draw from; `variants` receives each one's id once identical
// meshes share one, before look-alikes do (one variant = one distinct mesh).
std::vector<Shape> shape_pool(const ViewsOptions& opt, std::vector<std::string>& variants) {
  std::vector<std::string> classes = indoor_classes();
  for (const auto& c : outdoor_classes())
    if (std::find(classes.begin(), classes.end(), c) == classes.end()) classes.push_back(c);
  // About two instances per shape, so the same geometry is seen by several instances.
  const int procedural = opt.procedural ? std::max(int(classes.size()), opt.objects / 2) : 0;
  std::vector<Shape> pool;
  for (int k = 0; k < procedural; ++k)
    pool.push_back(make_shape(classes[size_t(k) % classes.size()], hash_combine(opt.seed, uint64_t(k)) & 0xFFFFFFFFull));
  for (const auto& s : opt.extra_shapes) pool.push_back(s);
  share_ids_of_identical_geometry(pool);
  for (const auto& s : pool) variants.push_back(s.id);
  share_ids_of_look_alikes(pool, static_cast<float>(opt.look_alike_tolerance));
  if (pool.empty()) throw Error("lista-sim views: no shapes to draw from (--no-procedural needs --furniture DIR with usable models)");
  return pool;
}

uint64_t view_key(uint64_t seed, int inst, int v, int attempt) {
  return hash_combine(hash_combine(seed, uint64_t(inst) + 1000003), uint64_t(v * 32 + attempt));
}

// One sweep from pose T (sensor -> object frame), appended in the object
// frame (the object stands at the world origin).
void scan_into(const RayScene& scene, const SensorModel& sensor, const Eigen::Isometry3d& T, uint64_t key, int threads,
               PointSet& cloud) {
  SweepOptions so;
  so.key = key;
  so.threads = threads;
  PointSet one = sweep(scene, nullptr, sensor, T, so);
  const Eigen::Isometry3f Tf = T.cast<float>();
  for (auto& p : one.xyz) cloud.xyz.push_back(Tf * p);
  cloud.intensity.insert(cloud.intensity.end(), one.intensity.begin(), one.intensity.end());
  cloud.label.insert(cloud.label.end(), one.label.begin(), one.label.end());
}

}  // namespace

ViewsStats write_views(const ViewsOptions& opt) {
  if (opt.out.empty()) throw Error("lista-sim views: --out is required");
  if (opt.objects < 1 || opt.views_per_object < 1 || opt.scans_per_view < 1)
    throw Error("lista-sim views: --objects, --views-per-object and --scans-per-view must be >= 1");
  // Sensors and pool first: an unknown sensor or an unusable shape set must
  // not cost the folder's old views.
  const std::vector<std::string> sensors = opt.sensors.empty() ? sensor_names() : opt.sensors;
  for (const auto& name : sensors) make_sensor(name);
  std::vector<std::string> variants;
  const std::vector<Shape> pool = shape_pool(opt, variants);
  const fs::path root(opt.out);
  if (fs::exists(root / "index.json") || fs::exists(root / "views")) {
    if (!opt.overwrite) throw Error("lista-sim views: " + opt.out + " already holds views (pass --overwrite)");
    fs::remove_all(root / "views");
    fs::remove(root / "index.json");
  }
  fs::create_directories(root / "views");

  nlohmann::json index;
  index["format"] = "lista-views/1";
  index["seed"] = opt.seed;
  index["look_alike_tolerance"] = opt.look_alike_tolerance;
  index["frame"] =
      "object: origin at the centre of the footprint on the floor, z up (gravity), x/y along the shape's own axes";
  nlohmann::json shapes = nlohmann::json::array(), views = nlohmann::json::array();
  std::vector<bool> shape_used(pool.size(), false);
  ViewsStats stats;

  for (int inst = 0; inst < opt.objects; ++inst) {
    Rng rng(opt.seed, hash_combine(hash_string("views"), uint64_t(inst)));
    const size_t si = size_t(rng.integer(0, int(pool.size()) - 1));
    const Shape& shape = pool[si];
    shape_used[si] = true;
    RayScene scene;
    scene.add(shape.mesh, Eigen::Isometry3f::Identity(), uint32_t(inst + 1), shape.reflectivity);
    scene.commit();
    for (int v = 0; v < opt.views_per_object; ++v) {
      PointSet cloud;
      std::string sensor_name;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      for (int attempt = 0; attempt < 20; ++attempt) {  // retry views that see (almost) nothing
        sensor_name = sensors[size_t(rng.integer(0, int(sensors.size()) - 1))];
        const SensorModel sensor = make_sensor(sensor_name);
        const double dist = 0.5 * shape.size() + rng.uniform(1.0, 8.0);
        const double az = rng.uniform(-M_PI, M_PI);
        const double height = rng.uniform(0.4, 1.8);
        T.linear() = Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), Eigen::Vector3d::UnitZ()).toRotationMatrix();
        T.translation() = Eigen::Vector3d(dist * std::cos(az), dist * std::sin(az), height);
        cloud = PointSet{};
        if (opt.scans_per_view > 1) {
          // The pass runs across the line of sight (within 30 deg), centred
          // on the first viewpoint, so it never crosses the object.
          const double heading = az + M_PI / 2 + rng.uniform(-M_PI / 6, M_PI / 6);
          const Eigen::Vector3d step(std::cos(heading), std::sin(heading), 0.0);
          for (int k = 0; k < opt.scans_per_view; ++k) {
            Eigen::Isometry3d Tk = T;
            Tk.translation() += (k - 0.5 * (opt.scans_per_view - 1)) * step;
            scan_into(scene, sensor, Tk, hash_combine(view_key(opt.seed, inst, v, attempt), uint64_t(k)), opt.threads,
                      cloud);
          }
        } else {
          scan_into(scene, sensor, T, view_key(opt.seed, inst, v, attempt), opt.threads, cloud);
        }
        if (cloud.size() >= 30) break;
      }
      char name[48];
      std::snprintf(name, sizeof(name), "views/%06d_%03d.pcd", inst, v);
      io::write_scan_pcd((root / name).string(), cloud, io::PcdEncoding::binary);
      views.push_back({{"file", name},
                       {"instance", inst + 1},
                       {"shape", shape.id},
                       {"variant", variants[si]},
                       {"class", shape.cls},
                       {"sensor", sensor_name},
                       {"viewpoint", {T.translation().x(), T.translation().y(), T.translation().z()}},
                       {"distance", T.translation().head<2>().norm()},
                       {"points", cloud.size()},
                       {"scans", opt.scans_per_view},
                       {"split", split_of(shape.id)}});
      ++stats.views;
      stats.points += cloud.size();
    }
    if (opt.progress) std::fprintf(stderr, "\rlista-sim views: object %d/%d", inst + 1, opt.objects);
  }
  if (opt.progress) std::fprintf(stderr, "\n");
  std::set<std::string> listed;
  for (size_t si = 0; si < pool.size(); ++si) {
    if (!shape_used[si] || !listed.insert(pool[si].id).second) continue;
    const Shape& s = pool[si];
    shapes.push_back({{"id", s.id},
                      {"class", s.cls},
                      {"source", s.source},
                      {"extent", {2 * s.half_extent.x(), 2 * s.half_extent.y(), s.height}},
                      {"split", split_of(s.id)}});
    ++stats.shapes;
  }
  index["shapes"] = shapes;
  index["views"] = views;
  io::write_file_atomic((root / "index.json").string(), index.dump(1) + "\n");
  return stats;
}

}  // namespace lista::sim
