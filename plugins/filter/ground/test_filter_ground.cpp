#include "ground_removal.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

using namespace test_support;

namespace {

// A floor patch z = f(x, y) with 1 cm noise, sampled every `step`; label 0.
void add_floor(lista::PointSet& s, float x0, float x1, float y0, float y1, float step,
               const std::function<float(float, float)>& f, std::mt19937& rng) {
  std::normal_distribution<float> noise(0.f, 0.01f);
  for (float x = x0; x < x1; x += step)
    for (float y = y0; y < y1; y += step) add_point(s, {x, y, f(x, y) + noise(rng)});
}

size_t count_if_in(const lista::PointSet& s, const std::vector<uint32_t>& ground,
                   const std::function<bool(const Eigen::Vector3f&)>& pred) {
  size_t n = 0;
  for (auto i : ground) n += pred(s.xyz[i]);
  return n;
}

}  // namespace

TEST(FilterGround, PlanePlusBoxRemovesGroundKeepsBox) {
  std::mt19937 rng(1);
  lista::PointSet s;
  add_floor(s, -3, 3, -3, 3, 0.05f, [](float, float) { return 0.f; }, rng);
  const size_t floor_points = s.size();
  add_box_surface(s, {0, 0, 0.02f}, {0.6f, 0.6f, 0.6f}, 0.04f);
  auto out = run_stage("filter.ground", "changes", lista::Data::make(missions({s})));
  const auto& kept = out.at("changes").as<lista::MissionPoints>().sets[0];
  size_t floor_kept = 0, box_kept = 0;
  for (auto i : kept.index) (i < floor_points ? floor_kept : box_kept)++;
  EXPECT_LT(floor_kept, floor_points / 100);
  // Everything of the box above the ground band survives.
  size_t box_above = 0;
  for (size_t i = floor_points; i < s.size(); ++i) box_above += s.xyz[i].z() > 0.12f;
  EXPECT_GE(box_kept, box_above);
  EXPECT_GT(box_kept, (s.size() - floor_points) * 3 / 4);
}

TEST(FilterGround, FollowsARampAcrossTiles) {
  std::mt19937 rng(2);
  lista::PointSet s;
  auto ramp = [](float x, float) { return 0.14f * x; };  // 8 degrees, 1.4 m rise over 10 m
  add_floor(s, 0, 10, 0, 3, 0.05f, ramp, rng);
  const size_t floor_points = s.size();
  add_box_surface(s, {7, 1, ramp(7.5f, 0) + 0.05f}, {7.5f, 1.5f, ramp(7.5f, 0) + 0.55f}, 0.04f);
  lista::filter::GroundConfig c;
  auto ground = lista::filter::find_ground(s, c, 2);
  size_t floor_removed = 0;
  for (auto i : ground) floor_removed += i < floor_points;
  EXPECT_GT(floor_removed, floor_points * 97 / 100);
  // Box points well above the ramp are never ground.
  EXPECT_EQ(count_if_in(s, ground, [&](const Eigen::Vector3f& p) { return p.z() > ramp(p.x(), 0) + 0.15f; }), 0u);
}

TEST(FilterGround, MultiLevelFloorsGoTableTopStays) {
  std::mt19937 rng(3);
  lista::PointSet s;
  // Lower level z=0 for x<2, upper level z=1.2 for x>=2, all in one 4 m tile.
  add_floor(s, 0, 2, 0, 3.9f, 0.05f, [](float, float) { return 0.f; }, rng);
  add_floor(s, 2, 3.9f, 0, 3.9f, 0.05f, [](float, float) { return 1.2f; }, rng);
  const size_t floor_points = s.size();
  // A table on the lower level: 1 x 1 m top at 0.75 m, four legs.
  for (float x = 0.5f; x <= 1.5f; x += 0.03f)
    for (float y = 1.0f; y <= 2.0f; y += 0.03f) add_point(s, {x, y, 0.75f});
  for (float lx : {0.52f, 1.48f})
    for (float ly : {1.02f, 1.98f})
      for (float z = 0.05f; z < 0.75f; z += 0.02f) add_point(s, {lx, ly, z});
  auto ground = lista::filter::find_ground(s, lista::filter::GroundConfig{}, 1);
  size_t floor_removed = 0;
  for (auto i : ground) floor_removed += i < floor_points;
  EXPECT_GT(floor_removed, floor_points * 95 / 100);
  EXPECT_EQ(count_if_in(s, ground, [](const Eigen::Vector3f& p) { return std::abs(p.z() - 0.75f) < 0.01f; }), 0u);
}

TEST(FilterGround, IsDeterministic) {
  std::mt19937 rng(4);
  lista::PointSet s;
  add_floor(s, -5, 5, -5, 5, 0.07f, [](float x, float y) { return 0.02f * x + 0.01f * y; }, rng);
  lista::filter::GroundConfig c;
  EXPECT_EQ(lista::filter::find_ground(s, c, 1), lista::filter::find_ground(s, c, 3));
}

TEST(FilterGround, SmallFlatObjectWithNothingUnderItStays) {
  std::mt19937 rng(5);
  lista::PointSet s;
  // A pallet deck, 1.2 x 0.8 m at 0.15 m (the floor under it is unchanged,
  // so not in the change cloud), two small patches of other objects at the
  // same height elsewhere in its tile; a floor sheet in the next tile.
  add_floor(s, 0.5f, 1.7f, 0.5f, 1.3f, 0.03f, [](float, float) { return 0.15f; }, rng);
  add_floor(s, 3.0f, 3.3f, 3.0f, 3.3f, 0.03f, [](float, float) { return 0.15f; }, rng);
  add_floor(s, 0.3f, 0.6f, 3.4f, 3.7f, 0.03f, [](float, float) { return 0.15f; }, rng);
  const size_t deck = s.size();
  add_floor(s, 4.5f, 7.5f, 0.5f, 3.5f, 0.05f, [](float, float) { return 0.f; }, rng);
  lista::filter::GroundConfig c;
  auto ground = lista::filter::find_ground(s, c, 1);
  EXPECT_EQ(count_if_in(s, ground, [](const Eigen::Vector3f& p) { return p.x() < 4.f; }), 0u);
  EXPECT_GT(ground.size(), (s.size() - deck) * 95 / 100);
  c.min_area = 0;  // without the area test the deck is taken for floor
  EXPECT_GT(lista::filter::find_ground(s, c, 1).size(), s.size() * 95 / 100);
}
