#include "views.hpp"

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

namespace lista::sim {
namespace fs = std::filesystem;

namespace {

// Shape-level split: all views of a shape land in the same split, so a model
// can be tested on shapes it never saw.
std::string split_of(const std::string& shape_id) {
  const uint64_t h = mix64(hash_string(shape_id.c_str())) % 10;
  return h < 8 ? "train" : (h == 8 ? "val" : "test");
}

std::vector<Shape> shape_pool(const ViewsOptions& opt) {
  std::vector<std::string> classes = indoor_classes();
  for (const auto& c : outdoor_classes())
    if (std::find(classes.begin(), classes.end(), c) == classes.end()) classes.push_back(c);
  // About two instances per shape, so the same geometry is seen by several instances.
  const int procedural = std::max(int(classes.size()), opt.objects / 2);
  std::vector<Shape> pool;
  for (int k = 0; k < procedural; ++k)
    pool.push_back(make_shape(classes[size_t(k) % classes.size()], hash_combine(opt.seed, uint64_t(k)) & 0xFFFFFFFFull));
  for (const auto& s : opt.extra_shapes) pool.push_back(s);
  return pool;
}

}  // namespace

ViewsStats write_views(const ViewsOptions& opt) {
  if (opt.out.empty()) throw Error("lista-sim views: --out is required");
  if (opt.objects < 1 || opt.views_per_object < 1)
    throw Error("lista-sim views: --objects and --views-per-object must be >= 1");
  const fs::path root(opt.out);
  if (fs::exists(root / "index.json") || fs::exists(root / "views")) {
    if (!opt.overwrite) throw Error("lista-sim views: " + opt.out + " already holds views (pass --overwrite)");
    fs::remove_all(root / "views");
    fs::remove(root / "index.json");
  }
  fs::create_directories(root / "views");

  const std::vector<Shape> pool = shape_pool(opt);
  nlohmann::json index;
  index["format"] = "lista-views/1";
  index["seed"] = opt.seed;
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
        sensor_name = sensor_names()[size_t(rng.integer(0, int(sensor_names().size()) - 1))];
        const SensorModel sensor = make_sensor(sensor_name);
        const double dist = 0.5 * shape.size() + rng.uniform(1.0, 8.0);
        const double az = rng.uniform(-M_PI, M_PI);
        const double height = rng.uniform(0.4, 1.8);
        T.linear() = Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), Eigen::Vector3d::UnitZ()).toRotationMatrix();
        T.translation() = Eigen::Vector3d(dist * std::cos(az), dist * std::sin(az), height);
        SweepOptions so;
        so.key = hash_combine(hash_combine(opt.seed, uint64_t(inst) + 1000003), uint64_t(v * 32 + attempt));
        so.threads = opt.threads;
        cloud = sweep(scene, nullptr, sensor, T, so);
        if (cloud.size() >= 30) break;
      }
      // Sensor frame -> object frame (the object stands at the world origin).
      const Eigen::Isometry3f Tf = T.cast<float>();
      for (auto& p : cloud.xyz) p = Tf * p;
      char name[48];
      std::snprintf(name, sizeof(name), "views/%06d_%03d.pcd", inst, v);
      io::write_scan_pcd((root / name).string(), cloud, io::PcdEncoding::binary);
      views.push_back({{"file", name},
                       {"instance", inst + 1},
                       {"shape", shape.id},
                       {"class", shape.cls},
                       {"sensor", sensor_name},
                       {"viewpoint", {T.translation().x(), T.translation().y(), T.translation().z()}},
                       {"distance", T.translation().head<2>().norm()},
                       {"points", cloud.size()},
                       {"split", split_of(shape.id)}});
      ++stats.views;
      stats.points += cloud.size();
    }
    if (opt.progress) std::fprintf(stderr, "\rlista-sim views: object %d/%d", inst + 1, opt.objects);
  }
  if (opt.progress) std::fprintf(stderr, "\n");
  for (size_t si = 0; si < pool.size(); ++si) {
    if (!shape_used[si]) continue;
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
