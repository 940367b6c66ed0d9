// The simulator's pieces on their own: footprints, placement without
// interpenetration, change kinds, sensor geometry and the Embree ray caster.
#include "footprint.hpp"
#include "furniture.hpp"
#include "layout.hpp"
#include "look_alikes.hpp"
#include "presets.hpp"
#include "raycaster.hpp"
#include "scanner.hpp"
#include "scenario.hpp"
#include "sensor.hpp"
#include "shapes.hpp"

#include <lista/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

using namespace lista::sim;

TEST(Footprint, SeparatingAxes) {
  Footprint a{{0, 0}, {1, 0.5}, 0.0};
  Footprint b{{2.5, 0}, {1, 0.5}, 0.0};
  EXPECT_FALSE(overlaps(a, b));
  EXPECT_TRUE(overlaps(a, b, 0.6));  // a 0.6 m gap requirement closes the 0.5 m gap
  b.yaw = M_PI / 2;                   // now 0.5 wide along x: still apart
  EXPECT_FALSE(overlaps(a, b));
  b.centre = {1.4, 0.0};
  EXPECT_TRUE(overlaps(a, b));
  Footprint c{{1.6, 1.6}, {0.5, 0.5}, M_PI / 4};  // diamond near a's corner, but apart
  EXPECT_FALSE(overlaps(a, c));
}

TEST(Shapes, EveryClassStandsOnTheFloorWithRealisticSize) {
  std::vector<std::string> classes = indoor_classes();
  for (const auto& c : outdoor_classes()) classes.push_back(c);
  for (const auto& cls : classes)
    for (uint64_t v = 0; v < 5; ++v) {
      const Shape s = make_shape(cls, v);
      Eigen::Vector3f lo, hi;
      s.mesh.bounds(lo, hi);
      EXPECT_NEAR(lo.z(), 0.0f, 1e-5) << s.id;
      EXPECT_NEAR(lo.x() + hi.x(), 0.0f, 1e-4) << s.id;
      EXPECT_GT(s.height, 0.1f) << s.id;
      EXPECT_LT(s.height, 3.5f) << s.id;
      EXPECT_GT(s.size(), 0.2f) << s.id;
      EXPECT_LT(s.size(), 13.0f) << s.id;
    }
  // Same variant, same geometry; another variant, other parameters.
  EXPECT_EQ(make_shape("chair", 3).mesh.vertices, make_shape("chair", 3).mesh.vertices);
  EXPECT_NE(make_shape("table", 3).half_extent, make_shape("table", 4).half_extent);
  EXPECT_THROW(make_shape("spaceship", 0), lista::Error);
}

// Pallets come in two sizes: forty variant numbers are two shapes, each
// named by its first variant; shapes with continuous parameters keep theirs.
TEST(Shapes, IdenticalGeometryIsOneShape) {
  std::vector<Shape> shapes;
  for (uint64_t v = 0; v < 40; ++v) shapes.push_back(make_shape("pallet", v));
  for (uint64_t v = 0; v < 10; ++v) shapes.push_back(make_shape("chair", v));
  share_ids_of_identical_geometry(shapes);
  std::set<std::string> pallets, chairs;
  for (const auto& s : shapes) (s.cls == "pallet" ? pallets : chairs).insert(s.id);
  EXPECT_EQ(pallets.size(), 2u);
  EXPECT_EQ(chairs.size(), 10u);
  EXPECT_EQ(shapes[0].id, "pallet#0");
  for (const auto& s : shapes)
    for (const auto& t : shapes)
      if (s.id == t.id) {
        EXPECT_EQ(s.mesh.vertices, t.mesh.vertices) << s.id;
      }
}

// Surfaces within a tolerance: a box against the same box grown by 5 mm on
// every side is within 1 cm but not within 2 mm; a 4 cm bump on one face
// is not within 3 cm; a panel 4-5 cm inside (bounds unchanged) is not
// within 3 cm but is within 6 cm.
TEST(LookAlikes, SurfacesWithinToleranceIsASymmetricHausdorffBound) {
  TriMesh box, grown, bumped;
  box.add_box({-0.5f, -0.3f, 0.0f}, {0.5f, 0.3f, 0.8f});
  grown.add_box({-0.505f, -0.305f, -0.005f}, {0.505f, 0.305f, 0.805f});
  EXPECT_TRUE(surfaces_within(box, grown, 0.01f));
  EXPECT_TRUE(surfaces_within(grown, box, 0.01f));
  EXPECT_FALSE(surfaces_within(box, grown, 0.002f));
  bumped = box;
  bumped.add_box({-0.05f, 0.3f, 0.3f}, {0.05f, 0.308f, 0.4f});  // 8 mm bump: within 1 cm
  EXPECT_TRUE(surfaces_within(box, bumped, 0.01f));
  bumped = box;
  bumped.add_box({-0.05f, 0.3f, 0.3f}, {0.05f, 0.34f, 0.4f});  // 4 cm bump in the middle of a side
  EXPECT_FALSE(surfaces_within(box, bumped, 0.03f));
  EXPECT_TRUE(surfaces_within(box, bumped, 0.045f));
  TriMesh dent = box;  // a panel 4 cm inside the box: bounds unchanged, the surface far from it
  dent.add_box({-0.3f, -0.26f, 0.2f}, {0.3f, -0.25f, 0.6f});
  EXPECT_FALSE(surfaces_within(box, dent, 0.03f));
  EXPECT_TRUE(surfaces_within(box, dent, 0.06f));
  EXPECT_FALSE(surfaces_within(box, TriMesh{}, 1.0f));
}

// Look-alikes join the first kept shape within tolerance, never a chain:
// boxes 1.5 cm apart in height share an id, the third (3 cm from the first,
// 1.5 cm from the second) keeps its own; tolerance 0 merges nothing.
TEST(LookAlikes, ShapesJoinTheFirstKeptShapeWithinTolerance) {
  auto box_shape = [](const std::string& id, float height) {
    Shape s;
    s.id = id;
    s.mesh.add_box({-0.4f, -0.4f, 0.0f}, {0.4f, 0.4f, height});
    return s;
  };
  std::vector<Shape> shapes = {box_shape("a", 1.0f), box_shape("b", 1.015f), box_shape("c", 1.03f),
                               box_shape("d", 1.5f)};
  std::vector<Shape> strict = shapes;
  share_ids_of_look_alikes(shapes, 0.02f);
  EXPECT_EQ(shapes[0].id, "a");
  EXPECT_EQ(shapes[1].id, "a");
  EXPECT_EQ(shapes[2].id, "c");
  EXPECT_EQ(shapes[3].id, "d");
  share_ids_of_look_alikes(strict, 0.0f);
  for (size_t i = 0; i < strict.size(); ++i) EXPECT_EQ(strict[i].id, std::string(1, char('a' + i)));
}

// A Sweet Home 3D catalogue as fetch-shapes.sh unpacks it: an L-shaped
// quad-and-triangle OBJ (y up, odd units, a negative index) sized by the
// catalogue; a door, a staircase and a broken model are left out.
TEST(Furniture, CatalogueMeshesStandOnTheFloorAtTheirCatalogueSize) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("lista_sim_furniture_" + std::to_string(::getpid()));
  fs::create_directories(dir / "lib" / "desk");
  std::ofstream(dir / "lib" / "desk" / "desk.obj") << "# y-up test mesh\nmtllib desk.mtl\n"
                                                       "v 0 0 0\nv 200 0 0\nv 200 50 0\nv 0 50 0\n"
                                                       "vt 0 0\nvn 0 1 0\nv 0 0 -80\n"
                                                       "f 1/1/1 2/1/1 3/1/1 4/1/1\nf 1//1 -1//1 2//1\n";
  std::ofstream(dir / "lib" / "broken.obj") << "v 0 0 0\nf 1 2 3\n";
  std::ofstream(dir / "lib" / "PluginFurnitureCatalog.properties")
      << "# catalogue\nid#1=Test#desk\nname#1=Desk\ncategory#1=Office\nmodel#1=/desk/desk.obj\n"
         "width#1=150\ndepth#1=70\nheight#1=75\n"
         "id#2=Test#door\nmodel#2=/desk/desk.obj\nwidth#2=90\ndepth#2=10\nheight#2=200\ndoorOrWindow#2=true\n"
         "id#3=Test#stairs\nmodel#3=/desk/desk.obj\nwidth#3=90\ndepth#3=200\nheight#3=250\n"
         "staircaseCutOutShape#3=M0,0 z\n"
         "id#4=Test#broken\nmodel#4=/broken.obj\nwidth#4=50\ndepth#4=50\nheight#4=50\n";
  const auto entries = read_catalog((dir / "lib" / "PluginFurnitureCatalog.properties").string());
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_TRUE(entries[1].door_or_window);
  EXPECT_TRUE(entries[2].staircase);
  std::vector<std::string> skipped;
  const std::vector<Shape> shapes = load_furniture(dir.string(), &skipped);
  ASSERT_EQ(shapes.size(), 1u);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find("broken.obj"), std::string::npos) << skipped[0];
  const Shape& desk = shapes[0];
  EXPECT_EQ(desk.mesh.triangles.size(), 3u);  // the quad is two triangles
  Eigen::Vector3f lo, hi;
  desk.mesh.bounds(lo, hi);
  EXPECT_NEAR(hi.x() - lo.x(), 1.50f, 1e-4f);
  EXPECT_NEAR(hi.y() - lo.y(), 0.70f, 1e-4f);
  EXPECT_NEAR(hi.z() - lo.z(), 0.75f, 1e-4f);
  EXPECT_NEAR(lo.z(), 0.0f, 1e-5f);
  EXPECT_EQ(desk.source, "sweethome3d");
  EXPECT_EQ(desk.cls, "sh3d/office");
  // SH3D's up (y) is our z: the three vertices with OBJ y = 0 lie on the floor.
  int on_floor = 0;
  for (const auto& v : desk.mesh.vertices) on_floor += std::abs(v.z()) < 1e-5f;
  EXPECT_EQ(on_floor, 3);
  std::ofstream(dir / "bad.properties") << "width#1=wide\n";
  try {
    read_catalog((dir / "bad.properties").string());
    ADD_FAILURE() << "a non-numeric width was read";
  } catch (const lista::Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.properties:1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_furniture((dir / "lib" / "desk").string()), lista::Error);  // no catalogue there
  fs::remove_all(dir);
}

TEST(Scenario, NoObjectInterpenetratesAnotherOrTheStructure) {
  for (const std::string name : {"tiny", "demo", "exp2", "exp3", "fsc"})
    for (uint64_t seed : {1, 2}) {
      const Preset p = make_preset(name);
      const Scenario sc = plan_scenario(build_layout(p.layout, seed), p.changes, p.route, seed);
      for (const auto& m : sc.missions) {
        std::vector<std::pair<uint32_t, Footprint>> fps;
        for (const auto& [id, pose] : m.objects) fps.emplace_back(id, footprint_of(sc.shapes[sc.object_shape.at(id)], pose));
        for (size_t i = 0; i < fps.size(); ++i) {
          for (size_t j = i + 1; j < fps.size(); ++j)
            EXPECT_FALSE(overlaps(fps[i].second, fps[j].second))
                << name << " seed " << seed << " mission " << m.name << ": " << fps[i].first << " vs " << fps[j].first;
          EXPECT_FALSE(overlaps_any(fps[i].second, sc.layout.obstacles)) << name << " object " << fps[i].first;
          EXPECT_FALSE(overlaps_any(fps[i].second, sc.layout.corridor())) << name << " object on the route";
        }
      }
    }
}

TEST(Scenario, ChangesOfEveryKindIncludingShortMovesAndSwaps) {
  const Preset p = make_preset("exp1");
  const Scenario sc = plan_scenario(build_layout(p.layout, 11), p.changes, p.route, 11);
  ASSERT_EQ(sc.missions.size(), 2u);
  const auto& a = sc.missions[0].objects;
  const auto& b = sc.missions[1].objects;
  int removed = 0, added = 0, short_moves = 0, swaps = 0;
  for (const auto& [id, pose] : a) {
    const auto it = b.find(id);
    if (it == b.end()) {
      ++removed;
      continue;
    }
    const double d = (it->second.translation() - pose.translation()).norm();
    const Shape& s = sc.shapes[sc.object_shape.at(id)];
    if (d > 0.05 && d < s.size()) ++short_moves;
    // A swap: another object of the same shape was where this one is now.
    for (const auto& [other, other_pose] : a)
      if (other != id && sc.object_shape.at(other) == sc.object_shape.at(id) &&
          (other_pose.translation() - it->second.translation()).norm() < 1e-9)
        ++swaps;
  }
  for (const auto& [id, pose] : b)
    if (!a.count(id)) ++added;
  EXPECT_EQ(removed, p.changes.removals);
  EXPECT_EQ(added, p.changes.additions);
  EXPECT_GE(short_moves, p.changes.short_moves);
  EXPECT_GE(swaps, 2 * p.changes.swaps);
  EXPECT_EQ(sc.missions[0].people.size(), size_t(p.changes.people));
}

// With 4 missions every mission pair gets its own changes, and the log
// keeps each of them (an object moved twice is logged twice), so the
// summary lista-sim prints counts them all.
TEST(Scenario, EveryChangeOfEveryMissionIsLogged) {
  const Preset p = make_preset("tiny");
  RouteParams route = p.route;
  route.missions = 4;
  const Scenario sc = plan_scenario(build_layout(p.layout, 1), p.changes, route, 1);
  ASSERT_EQ(sc.missions.size(), 4u);
  int added = 0, logged_added = 0;
  for (size_t m = 1; m < sc.missions.size(); ++m)
    for (const auto& [id, pose] : sc.missions[m].objects)
      if (!sc.missions[m - 1].objects.count(id)) ++added;
  for (const auto& [id, kinds] : sc.change_kind)
    logged_added += int(std::count(kinds.begin(), kinds.end(), "added"));
  EXPECT_EQ(added, 3 * p.changes.additions);
  EXPECT_EQ(logged_added, added);
}

TEST(Sensor, BeamTablesMatchTheDatasheets) {
  const SensorModel os0 = make_sensor("os0-128");
  EXPECT_EQ(os0.elevations.size(), 128u);
  EXPECT_NEAR(os0.elevations.front(), -M_PI / 4, 1e-9);
  EXPECT_NEAR(os0.elevations.back(), M_PI / 4, 1e-9);
  EXPECT_EQ(os0.columns, 1024);
  const SensorModel xt = make_sensor("xt32");
  EXPECT_EQ(xt.elevations.size(), 32u);
  EXPECT_NEAR(xt.elevations.front() * 180 / M_PI, -16.0, 1e-9);
  EXPECT_NEAR(xt.elevations.back() * 180 / M_PI, 15.0, 1e-9);
  EXPECT_EQ(xt.max_range, 120.0);
  EXPECT_EQ(make_sensor("vlp16").elevations.size(), 16u);
  EXPECT_EQ(make_sensor("vlp16", 900).columns, 900);
  const SensorModel os1 = make_sensor("os1-64");
  EXPECT_EQ(os1.elevations.size(), 64u);
  EXPECT_NEAR((os1.elevations.back() - os1.elevations.front()) * 180 / M_PI, 42.4, 1e-9);
  const SensorModel hdl = make_sensor("hdl32");
  EXPECT_EQ(hdl.elevations.size(), 32u);
  EXPECT_NEAR(hdl.elevations.front() * 180 / M_PI, -30.67, 1e-9);
  EXPECT_NEAR((hdl.elevations[1] - hdl.elevations[0]) * 180 / M_PI, 1.33, 0.01);
  try {
    make_sensor("lidar9000");
    ADD_FAILURE() << "an unknown sensor was accepted";
  } catch (const lista::Error& e) {
    EXPECT_NE(std::string(e.what()).find("use one of os0-128, xt32, vlp16, os1-64, hdl32, tls, mid360, avia"), std::string::npos)
        << e.what();
  }
  for (const auto& name : all_sensor_names()) EXPECT_EQ(make_sensor(name).name, name);
  EXPECT_EQ(sensor_names(), (std::vector<std::string>{"os0-128", "xt32", "vlp16"}));  // the default draw
}

// Livox scanners have no rings: every sweep spreads its rays evenly over
// the field of view, from a start of its own, so two sweeps from one spot
// see different points while one key always gives the same sweep.
TEST(Sensor, NonRepetitiveScannersCoverTheirFieldOfViewAndNeverRepeat) {
  RayScene room;  // a closed 20 m box around the sensor: every ray hits
  TriMesh box;
  box.add_box({-10.0f, -10.0f, -10.0f}, {10.0f, 10.0f, -9.9f});
  box.add_box({-10.0f, -10.0f, 9.9f}, {10.0f, 10.0f, 10.0f});
  box.add_box({-10.0f, -10.0f, -10.0f}, {-9.9f, 10.0f, 10.0f});
  box.add_box({9.9f, -10.0f, -10.0f}, {10.0f, 10.0f, 10.0f});
  box.add_box({-10.0f, -10.0f, -10.0f}, {10.0f, -9.9f, 10.0f});
  box.add_box({-10.0f, 9.9f, -10.0f}, {10.0f, 10.0f, 10.0f});
  room.add(box, Eigen::Isometry3f::Identity(), 0, 0.8f);
  room.commit();
  auto degrees = [](double rad) { return rad * 180.0 / M_PI; };
  for (const std::string name : {"mid360", "avia"}) {
    SCOPED_TRACE(name);
    SensorModel s = make_sensor(name);
    ASSERT_TRUE(s.non_repetitive());
    EXPECT_TRUE(s.elevations.empty());
    s.dropout = 0.0;
    s.range_sigma = 0.0;
    SweepOptions so;
    so.threads = 2;
    so.key = 7;
    const lista::PointSet a = sweep(room, nullptr, s, Eigen::Isometry3d::Identity(), so);
    a.check_consistent();
    ASSERT_GT(a.size(), s.rays() * 99 / 100);  // grazing incidence loses a few
    std::vector<int> azimuth_bins(36, 0), elevation_bins(10, 0);
    for (const auto& p : a.xyz) {
      const double elevation = std::asin(p.z() / p.norm()), azimuth = std::atan2(p.y(), p.x());
      ASSERT_GE(elevation, s.elevation_min - 1e-5);
      ASSERT_LE(elevation, s.elevation_max + 1e-5);
      ASSERT_LE(std::abs(azimuth), s.azimuth_fov / 2 + 1e-5);
      ++azimuth_bins[std::min(35, int((azimuth + s.azimuth_fov / 2) / s.azimuth_fov * 36))];
      ++elevation_bins[std::min(9, int((elevation - s.elevation_min) / (s.elevation_max - s.elevation_min) * 10))];
    }
    for (int n : azimuth_bins) EXPECT_NEAR(n, a.size() / 36.0, a.size() / 36.0 * 0.05);
    // Even per solid angle: the lowest and highest tenth hold about what cos(elevation) says.
    const double lo = degrees(s.elevation_min), hi = degrees(s.elevation_max);
    EXPECT_LT(elevation_bins[9], elevation_bins[0] * std::cos((hi - (hi - lo) / 20) * M_PI / 180) /
                                     std::cos((lo + (hi - lo) / 20) * M_PI / 180) * 1.1);
    const lista::PointSet again = sweep(room, nullptr, s, Eigen::Isometry3d::Identity(), so);
    EXPECT_EQ(again.xyz, a.xyz);
    so.key = 8;
    const lista::PointSet other = sweep(room, nullptr, s, Eigen::Isometry3d::Identity(), so);
    ASSERT_EQ(other.size(), a.size());
    size_t same = 0;
    for (size_t i = 0; i < a.size(); ++i) same += (other.xyz[i] - a.xyz[i]).norm() < 1e-3f;
    EXPECT_LT(same, a.size() / 100);
  }
  EXPECT_NEAR(degrees(make_sensor("mid360").elevation_min), -7.0, 1e-9);
  EXPECT_NEAR(degrees(make_sensor("avia").azimuth_fov), 70.4, 1e-9);
  EXPECT_THROW(make_sensor("mid360", 900), lista::Error);  // no columns to set
}

TEST(RayScene, HitsAWallAtTheRightRangeWithItsLabel) {
  RayScene scene;
  TriMesh wall;
  wall.add_box({5.0f, -10.0f, -10.0f}, {5.2f, 10.0f, 10.0f});
  scene.add(wall, Eigen::Isometry3f::Identity(), 42, 0.8f);
  scene.commit();
  const Hit h = scene.intersect({0, 0, 0}, {1, 0, 0}, 0.1f, 100.0f);
  EXPECT_NEAR(h.t, 5.0f, 1e-5);
  EXPECT_EQ(h.label, 42u);
  EXPECT_NEAR(std::abs(h.normal.x()), 1.0f, 1e-5);
  EXPECT_LT(scene.intersect({0, 0, 0}, {-1, 0, 0}, 0.1f, 100.0f).t, 0.0f);  // nothing behind
  EXPECT_LT(scene.intersect({0, 0, 0}, {1, 0, 0}, 0.1f, 4.0f).t, 0.0f);     // beyond max range

  // A full sweep inside: every point near 5 m along x, labelled 42, noise ~cm.
  SensorModel s = make_sensor("vlp16", 360);
  s.dropout = 0.0;
  SweepOptions so;
  so.threads = 2;
  const lista::PointSet pts = sweep(scene, nullptr, s, Eigen::Isometry3d::Identity(), so);
  ASSERT_GT(pts.size(), 1000u);
  pts.check_consistent();
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(pts.xyz[i].x(), 5.0f, 0.1f);
    EXPECT_EQ(pts.label[i], 42u);
  }
}

// lista-sim --drift scales the odometry drift (RouteParams): the same seed
// gives the same random walk, so heading error grows exactly with the
// factor, position error nearly so; 0 gives the true poses.
TEST(Scenario, OdometryDriftScalesWithTheRouteParams) {
  const Preset p = make_preset("hall");
  auto end_error = [&](double factor) {
    RouteParams route = p.route;
    route.drift_per_m *= factor;
    route.yaw_drift_deg_per_m *= factor;
    const Scenario sc = plan_scenario(build_layout(p.layout, 3), p.changes, route, 3);
    const MissionPlan& m = sc.missions.back();
    const Eigen::Isometry3d est = m.map_to_world * m.poses_estimated.back(), truth = m.poses_true.back();
    const Eigen::Isometry3d error = truth.inverse() * est;
    return std::make_pair(error.translation().norm(), Eigen::AngleAxisd(error.linear()).angle());
  };
  const auto none = end_error(0.0), once = end_error(1.0), five = end_error(5.0);
  EXPECT_LT(none.first, 1e-9);
  EXPECT_LT(none.second, 1e-9);
  ASSERT_GT(once.first, 1e-3);
  EXPECT_NEAR(five.second, 5.0 * once.second, 1e-9);
  EXPECT_GT(five.first, 4.5 * once.first);
  EXPECT_LT(five.first, 5.5 * once.first);
}

// --operator: one more person per mission, standing 1.5-2.5 m behind the
// sensor at every scan and somewhere else each scan; nothing else drawn
// changes (its own random stream).
TEST(Scenario, TheOperatorStandsBesideEveryStationAndChangesNothingElse) {
  const Preset p = make_preset("tiny");
  ChangeParams with = p.changes;
  with.station_operator = true;
  const Scenario plain = plan_scenario(build_layout(p.layout, 3), p.changes, p.route, 3);
  const Scenario sc = plan_scenario(build_layout(p.layout, 3), with, p.route, 3);
  ASSERT_EQ(sc.missions.size(), plain.missions.size());
  for (size_t m = 0; m < sc.missions.size(); ++m) {
    const MissionPlan& mission = sc.missions[m];
    EXPECT_EQ(mission.objects.size(), plain.missions[m].objects.size());
    ASSERT_EQ(mission.poses_true.size(), plain.missions[m].poses_true.size());
    for (size_t i = 0; i < mission.poses_true.size(); ++i)
      EXPECT_TRUE(mission.poses_true[i].isApprox(plain.missions[m].poses_true[i]));
    ASSERT_EQ(mission.people.size(), plain.missions[m].people.size() + 1);
    const Person& op = mission.people.back();
    EXPECT_TRUE(op.beside_sensor);
    std::set<std::pair<long, long>> places;
    for (size_t i = 0; i < mission.poses_true.size(); ++i) {
      const Eigen::Vector2d at = mission.person_pose(op, i).translation().head<2>();
      const double d = (at - mission.poses_true[i].translation().head<2>()).norm();
      EXPECT_GT(d, 1.3);
      EXPECT_LT(d, 2.8);
      places.insert({std::lround(at.x() * 10), std::lround(at.y() * 10)});
    }
    EXPECT_GT(places.size(), mission.poses_true.size() / 2) << "the operator should move between scans";
  }
}
