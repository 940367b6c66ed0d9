#include <lista_testing/point_scenes.hpp>
#include "body_detector.hpp"

#include <lista_alignkit/synthetic_scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace {

using lista::alignkit::testing::Box;
using lista::alignkit::testing::Scene;

// Adds `n` points on a legged robot's back under the sensor to every scan (a
// 1.1 x 0.5 m box top 0.15 m below it, sides down to 0.45 m), numbered after
// the scan's own points. Returns how many were added.
size_t add_body(lista::Mission& m, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  size_t added = 0;
  for (size_t s = 0; s < m.scans.size(); ++s) {
    auto points = std::make_shared<lista::PointSet>(*m.scans[s].points);
    for (int k = 0; k < n; ++k) {
      const float x = -0.9f + 1.1f * u(rng), y = -0.25f + 0.5f * u(rng), z = -0.45f + 0.3f * u(rng);
      const float face = u(rng);
      Eigen::Vector3f p = face < 0.6f ? Eigen::Vector3f(x, y, -0.15f)
                          : face < 0.8f ? Eigen::Vector3f(x, u(rng) < 0.5f ? -0.25f : 0.25f, z)
                                        : Eigen::Vector3f(u(rng) < 0.5f ? -0.9f : 0.2f, y, z);
      points->xyz.push_back(p);
      points->scan.push_back(uint32_t(s));
      points->index.push_back(m.scans[s].points_in_file + uint32_t(k));
    }
    m.scans[s].points_in_file += uint32_t(n);
    m.scans[s].points = std::move(points);
    added += size_t(n);
  }
  return added;
}

lista::MissionSet one_mission(lista::Mission m) {
  lista::MissionSet set;
  set.missions.push_back(std::move(m));
  return set;
}

lista::Mission hall_mission(const std::vector<Eigen::Isometry3d>& route) {
  const Scene hall = lista::alignkit::testing::make_hall(20, 14, 12, 3);
  return lista::alignkit::testing::make_mission("A", hall, route, route, 5);
}

// The body's points of each scan are those numbered from `first[s]` on.
size_t points_of(const lista::MissionSet& set) {
  size_t n = 0;
  for (const auto& m : set.missions) n += m.point_count();
  return n;
}

struct Dropped {
  size_t body = 0, scene = 0;
};

Dropped count_dropped(const lista::Mission& before, const lista::Mission& after, const std::vector<uint32_t>& first) {
  Dropped d;
  for (size_t s = 0; s < before.scans.size(); ++s) {
    std::set<uint32_t> kept(after.scans[s].points->index.begin(), after.scans[s].points->index.end());
    for (const uint32_t i : before.scans[s].points->index)
      if (!kept.count(i)) ++(i >= first[s] ? d.body : d.scene);
  }
  return d;
}

std::vector<uint32_t> scene_point_counts(const lista::Mission& m) {
  std::vector<uint32_t> n;
  for (const auto& s : m.scans) n.push_back(s.points_in_file);
  return n;
}

const lista::Mission& only(const lista::Outputs& out) {
  return out.at("missions").as<lista::MissionSet>().missions.at(0);
}

}  // namespace

TEST(FilterBody, DropsTheBodyOfAWalkingRobotAndKeepsTheHall) {
  lista::Mission m = hall_mission(lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0));
  const std::vector<uint32_t> first = scene_point_counts(m);
  const size_t body = add_body(m, 300, 1);
  const lista::Mission before = m;
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(one_mission(m)));
  const Dropped d = count_dropped(before, only(out), first);
  // One thread finds the same points.
  const auto serial = test_support::run_stage("filter.body", "missions", lista::Data::make(one_mission(m)), {}, 1);
  EXPECT_EQ(only(serial).point_count(), only(out).point_count());
  EXPECT_GE(double(d.body), 0.97 * double(body));
  EXPECT_EQ(d.scene, 0u);
  // Kept points keep their scan and file index.
  const auto& kept = *only(out).scans[3].points;
  EXPECT_LT(std::count_if(kept.index.begin(), kept.index.end(), [&](uint32_t i) { return i >= first[3]; }), 30);
  EXPECT_TRUE(std::is_sorted(kept.index.begin(), kept.index.end()));
  EXPECT_EQ(kept.scan.front(), 3u);
}

// With scans left unread (io.missions scan_spacing) or empty, only the
// scans holding points count and witness.
TEST(FilterBody, EmptyScansNeitherCountNorWitness) {
  lista::Mission m = hall_mission(lista::alignkit::testing::loop_route(20, 14, 4, 0.75, 0.0));
  const std::vector<uint32_t> first = scene_point_counts(m);
  add_body(m, 300, 6);
  size_t body = 0;
  for (size_t s = 0; s < m.scans.size(); ++s)
    if (s % 3 != 0) {
      m.scans[s].points = std::make_shared<const lista::PointSet>();
    } else {
      body += 300;
    }
  const lista::Mission before = m;
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(one_mission(m)));
  const Dropped d = count_dropped(before, only(out), first);
  EXPECT_GE(double(d.body), 0.97 * double(body));
  EXPECT_EQ(d.scene, 0u);
}

TEST(FilterBody, DropsARayCastBodySeenByAFewRings) {
  // The body as a 16-ring sensor sees it: a box in the scene that moves with
  // the sensor and hides what lies behind it, hit by a few rings in arcs.
  const Scene hall = lista::alignkit::testing::make_hall(20, 14, 12, 3);
  const std::vector<Eigen::Isometry3d> route = lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0);
  lista::Mission m;
  m.name = "A";
  std::mt19937 rng(4);
  size_t body = 0;
  std::vector<std::vector<char>> is_body;
  for (size_t i = 0; i < route.size(); ++i) {
    // The route turns by quarter turns only, so the turned box stays axis-aligned.
    const Eigen::Vector3d a = route[i] * Eigen::Vector3d(-0.9, -0.25, -0.45);
    const Eigen::Vector3d b = route[i] * Eigen::Vector3d(0.2, 0.25, -0.15);
    Scene scene = hall;
    scene.boxes.push_back({a.cwiseMin(b), a.cwiseMax(b)});
    lista::Scan scan;
    scan.pose = route[i];
    auto points = std::make_shared<lista::PointSet>(lista::alignkit::testing::cast_scan(scene, route[i], uint32_t(i), rng));
    is_body.emplace_back();
    for (const auto& p : points->xyz) {
      const bool on = (p.cast<double>() - Eigen::Vector3d(-0.35, 0, -0.3)).cwiseAbs().maxCoeff() < 0.6 &&
                      std::abs(p.y()) < 0.3 && p.z() < -0.1 && p.z() > -0.5;
      is_body.back().push_back(on);
      body += on;
    }
    scan.points_in_file = uint32_t(points->size());
    scan.points = std::move(points);
    m.scans.push_back(std::move(scan));
  }
  ASSERT_GT(body, 20 * route.size());
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(one_mission(m)));
  size_t body_dropped = 0, scene_dropped = 0;
  for (size_t s = 0; s < m.scans.size(); ++s) {
    std::set<uint32_t> kept(only(out).scans[s].points->index.begin(), only(out).scans[s].points->index.end());
    for (size_t k = 0; k < m.scans[s].points->size(); ++k)
      if (!kept.count(m.scans[s].points->index[k])) ++(is_body[s][k] ? body_dropped : scene_dropped);
  }
  EXPECT_GE(double(body_dropped), 0.95 * double(body));
  EXPECT_EQ(scene_dropped, 0u);
}

TEST(FilterBody, KeepsTheWallsAndFloorOfACorridorThatStayBesideTheSensor) {
  // Walls 1 m either side of a straight route, the sensor 0.35 m above the
  // floor: in the sensor frame walls and floor stay put like a body, but
  // every other scan sees them where they are (the floor at a grazing angle).
  Scene corridor;
  corridor.boxes.push_back({{-5, -3, -0.1}, {40, 3, 0}});
  corridor.boxes.push_back({{-5, -1.2, 0}, {40, -1.0, 3}});
  corridor.boxes.push_back({{-5, 1.0, 0}, {40, 1.2, 3}});
  corridor.boxes.push_back({{-5, -3, 2.6}, {40, 3, 2.7}});
  std::vector<Eigen::Isometry3d> route;
  for (int i = 0; i < 24; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(1.0 + 1.2 * i, 0.0, 0.35);
    route.push_back(pose);
  }
  lista::Mission m = lista::alignkit::testing::make_mission("A", corridor, route, route, 2);
  const lista::Mission before = m;
  const lista::MissionSet in = one_mission(std::move(m));
  const lista::filter::BodyCells cells = lista::filter::find_body_cells(in.missions[0], {});
  EXPECT_GT(cells.candidates, 20u);  // the walls do stay put in the sensor frame
  EXPECT_GT(cells.voted, 20u);
  EXPECT_EQ(cells.confirmed, 0u);
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(in));
  EXPECT_EQ(only(out).point_count(), before.point_count());
}

TEST(FilterBody, LeavesARobotStandingStillAlone) {
  // Without a scan taken elsewhere nothing can see through the body.
  std::vector<Eigen::Isometry3d> route(12, lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0)[0]);
  lista::Mission m = hall_mission(route);
  add_body(m, 300, 2);
  const size_t n = m.point_count();
  const lista::MissionSet in = one_mission(std::move(m));
  EXPECT_FALSE(lista::filter::find_body_cells(in.missions[0], {}).checked);
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(in));
  EXPECT_EQ(only(out).point_count(), n);
}

// A robot that stands for half its mission 1 m from a wall (a dock) and
// then walks: the wall stays put in the sensor frame for half the scans,
// but the scans taken while walking see it where it is.
TEST(FilterBody, KeepsAWallBesideARobotThatStoodStillHalfTheMission) {
  const Scene hall = lista::alignkit::testing::make_hall(20, 14, 12, 3);
  std::vector<Eigen::Isometry3d> route(30, Eigen::Isometry3d::Identity());
  for (auto& pose : route) pose.translation() = Eigen::Vector3d(1.0, 7.0, 1.0);  // 1 m from the wall at x = 0
  for (const auto& walk : lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0)) route.push_back(walk);
  lista::Mission m = lista::alignkit::testing::make_mission("A", hall, route, route, 8);
  const size_t n = m.point_count();
  const lista::MissionSet in = one_mission(std::move(m));
  const lista::filter::BodyCells cells = lista::filter::find_body_cells(in.missions[0], {});
  EXPECT_GT(cells.candidates, 10u);  // the wall, in 30 of 54 scans
  EXPECT_EQ(cells.confirmed, 0u);
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(in));
  EXPECT_EQ(only(out).point_count(), n);
}

TEST(FilterBody, MaxRangeZeroTurnsItOff) {
  lista::Mission m = hall_mission(lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0));
  add_body(m, 300, 3);
  const size_t n = m.point_count();
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(one_mission(std::move(m))),
                                           {{"max_range", 0.0}});
  EXPECT_EQ(only(out).point_count(), n);
}

TEST(FilterBody, RejectsSettingsThatCannotWork) {
  const lista::MissionSet set = one_mission(hall_mission(lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0)));
  EXPECT_THROW(test_support::run_stage("filter.body", "missions", lista::Data::make(set),
                                       {{"witness_min", 5.0}, {"witness_max", 3.0}}),
               lista::Error);
  // A ray passing within a cell of a point a cell under the floor grazes the floor.
  EXPECT_THROW(test_support::run_stage("filter.body", "missions", lista::Data::make(set),
                                       {{"depth", 0.1}, {"cell", 0.1}}),
               lista::Error);
}

namespace {

// Two stop-and-go missions of one scan each, from stations `a` and `b` of
// the hall's loop, each scan with the platform under its sensor when
// `platform` (seen densely, as a scanner sees what carries it at 1 m).
constexpr int kPlatformPoints = 3000;

lista::MissionSet two_stations(size_t a, size_t b, bool platform) {
  const Scene hall = lista::alignkit::testing::make_hall(20, 14, 12, 3);
  const auto loop = lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0);
  lista::MissionSet set;
  for (const size_t station : {a, b}) {
    const std::vector<Eigen::Isometry3d> route{loop[station]};
    lista::Mission m = lista::alignkit::testing::make_mission(set.missions.empty() ? "A" : "B", hall, route, route,
                                                           uint32_t(11 + station));
    if (platform) add_body(m, kPlatformPoints, uint32_t(station));
    set.missions.push_back(std::move(m));
  }
  return set;
}

}  // namespace

// One scan per mission leaves no witness in the mission, but the platform
// stands at the same place in the sensor frame at both stations, and the
// hall around them does not: the platform goes, the hall stays.
TEST(FilterBody, DropsThePlatformOfOneScanStations) {
  const lista::MissionSet in = two_stations(2, 9, true);
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(in));
  const auto& after = out.at("missions").as<lista::MissionSet>();
  for (size_t m = 0; m < 2; ++m) {
    const Dropped d = count_dropped(in.missions[m], after.missions[m],
                                    {in.missions[m].scans[0].points_in_file - uint32_t(kPlatformPoints)});
    EXPECT_GE(double(d.body), 0.97 * kPlatformPoints) << in.missions[m].name;
    EXPECT_EQ(d.scene, 0u) << in.missions[m].name;
  }
  // One thread drops the same points.
  const auto serial = test_support::run_stage("filter.body", "missions", lista::Data::make(in), {}, 1);
  EXPECT_EQ(points_of(serial.at("missions").as<lista::MissionSet>()), points_of(after));
}

TEST(FilterBody, KeepsEverythingOfOneScanStationsWithoutAPlatform) {
  const lista::MissionSet in = two_stations(2, 9, false);
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(in));
  EXPECT_EQ(points_of(out.at("missions").as<lista::MissionSet>()), points_of(in));
}

namespace {

// Appends `points` (sensor frame) to the first scan of `m`, numbered after
// its points; returns the first new index.
uint32_t append_points(lista::Mission& m, const std::vector<Eigen::Vector3f>& points) {
  lista::Scan& scan = m.scans.at(0);
  auto set = std::make_shared<lista::PointSet>(*scan.points);
  const uint32_t first = scan.points_in_file;
  for (size_t k = 0; k < points.size(); ++k) {
    set->xyz.push_back(points[k]);
    set->scan.push_back(0);
    set->index.push_back(first + uint32_t(k));
  }
  scan.points_in_file += uint32_t(points.size());
  scan.points = std::move(set);
  return first;
}

}  // namespace

// The floor under a scanner kept at one height is at one place at every
// station, like the platform; a crate on it beside one station is not, and
// keeps its points (all but those in the floor's own cells).
TEST(FilterBody, KeepsAnObjectOnTheFloorBesideOneStation) {
  lista::MissionSet in = two_stations(2, 9, true);
  constexpr float floor_z = -0.55f;
  std::vector<Eigen::Vector3f> floor, crate;
  for (float x = -1.4f; x <= 1.4f; x += 0.05f)
    for (float y = -1.4f; y <= 1.4f; y += 0.05f)
      if (x * x + y * y < 1.4f * 1.4f) floor.emplace_back(x, y, floor_z);
  for (float a = 0.f; a <= 0.3f; a += 0.02f)
    for (float z = floor_z; z <= -0.2f; z += 0.02f) {
      crate.emplace_back(0.8f, a - 0.15f, z);  // the face toward the sensor
      crate.emplace_back(0.8f + a, -0.15f, z);
      crate.emplace_back(0.8f + a, 0.15f, z);
    }
  for (auto& m : in.missions) append_points(m, floor);
  const uint32_t first_crate = append_points(in.missions[1], crate);
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(in));
  const lista::PointSet& kept = *out.at("missions").as<lista::MissionSet>().missions[1].scans[0].points;
  const std::set<uint32_t> kept_index(kept.index.begin(), kept.index.end());
  size_t above_floor_cells = 0, kept_crate = 0;
  for (size_t k = 0; k < crate.size(); ++k) {
    if (crate[k].z() < -0.5f) continue;  // the floor's cells: taken with it
    ++above_floor_cells;
    kept_crate += kept_index.count(first_crate + uint32_t(k));
  }
  EXPECT_GT(above_floor_cells, 300u);
  EXPECT_EQ(kept_crate, above_floor_cells);
  EXPECT_LT(kept.size(), in.missions[1].scans[0].points->size() - floor.size() / 2);  // the floor went
}

// A single station has nothing to be compared with: it is left alone.
TEST(FilterBody, LeavesALoneStationAlone) {
  lista::MissionSet in = two_stations(2, 9, true);
  in.missions[1] = hall_mission(lista::alignkit::testing::loop_route(20, 14, 4, 1.5, 0.0));
  in.missions[1].name = "B";
  const size_t station_points = in.missions[0].point_count();
  const auto out = test_support::run_stage("filter.body", "missions", lista::Data::make(in));
  EXPECT_EQ(out.at("missions").as<lista::MissionSet>().missions[0].point_count(), station_points);
}
