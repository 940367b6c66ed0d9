#include "../../group/kmeans/stage_harness.hpp"
#include "weighted_matcher.hpp"

#include <lista/basic_context.hpp>

#include <gtest/gtest.h>
#include <random>

using namespace lista;
using namespace lista::matching;

namespace {

struct Scene {
  ObjectSet objects;
  DescriptorSet descriptors;
  // Adds an object (a small point blob) at `at` in mission `m` with descriptor `d`.
  // `size` scales the blob (a 0.1 m cube by default).
  int add(uint32_t m, Eigen::Vector3f at, std::vector<float> d, Eigen::Vector3f size = Eigen::Vector3f::Constant(0.1f)) {
    Object o;
    o.id = static_cast<int>(objects.objects.size());
    o.mission = m;
    for (int i = 0; i < 8; ++i) {
      o.points.xyz.push_back(at + Eigen::Vector3f(i & 1, (i >> 1) & 1, (i >> 2) & 1).cwiseProduct(size));
      o.points.scan.push_back(0);
      o.points.index.push_back(i);
    }
    o.update_geometry();
    objects.objects.push_back(o);
    const int r = static_cast<int>(descriptors.values.rows());
    descriptors.values.conservativeResize(r + 1, static_cast<int>(d.size()));
    for (size_t k = 0; k < d.size(); ++k) descriptors.values(r, k) = d[k];
    descriptors.object_ids.push_back(o.id);
    return o.id;
  }
};

const std::vector<float> chair{1, 0, 0, 0}, table{0, 1, 0, 0}, lamp{0, 0, 1, 0};

Matches run_stage(const Scene& s, std::map<std::string, ParamValue> p = {}, const Groups* g = nullptr) {
  auto stage = stage_test::make_stage("match.weighted", p);
  BasicContext ctx;
  Inputs in;
  in.set("objects", Data::make(s.objects));
  in.set("descriptors", Data::make(s.descriptors));
  if (g) in.set("groups", Data::make(*g));
  return stage->run(in, ctx).at("matches").as<Matches>();
}

}  // namespace

TEST(MatchWeighted, OneMovedOneRemovedOneAdded) {
  Scene s;
  s.objects.missions = {"A", "B"};
  const int chair_a = s.add(0, {0, 0, 0}, chair);
  const int table_a = s.add(0, {-8, 4, 0}, table, {1.2f, 0.8f, 0.75f});
  const int chair_b = s.add(1, {1.5, 0.5, 0}, chair);
  const int lamp_b = s.add(1, {9, -4, 0}, lamp, {0.3f, 0.3f, 1.6f});
  const Matches m = run_stage(s);
  ASSERT_EQ(m.objects.size(), 4u);
  EXPECT_EQ(m.find(chair_a)->status, ChangeStatus::moved);
  EXPECT_EQ(m.find(chair_a)->match, chair_b);
  EXPECT_EQ(m.find(chair_b)->status, ChangeStatus::moved);
  EXPECT_EQ(m.find(chair_b)->match, chair_a);
  EXPECT_EQ(m.find(table_a)->status, ChangeStatus::removed);
  EXPECT_EQ(m.find(lamp_b)->status, ChangeStatus::added);
  EXPECT_EQ(m.find(table_a)->match, -1);
  EXPECT_EQ(m.find(chair_a)->history, (std::vector<int>{chair_a, chair_b}));
  EXPECT_EQ(m.find(lamp_b)->history, (std::vector<int>{lamp_b}));
  for (const auto& c : m.objects) {
    EXPECT_GE(c.confidence, 0.0);
    EXPECT_LE(c.confidence, 1.0);
  }
}

TEST(MatchWeighted, SwapOfIdenticalObjectsResolvedByPhysicalDistance) {
  // Two chairs of one model, each nudged a little; descriptors differ only by
  // noise, which (in the worst pairing) favours the crossed assignment.
  Scene s;
  s.objects.missions = {"A", "B"};
  const int a1 = s.add(0, {0, 0, 0}, {1.00f, 0.02f, 0, 0});
  const int a2 = s.add(0, {3, 0, 0}, {1.00f, 0.00f, 0, 0});
  const int b1 = s.add(1, {0.4f, 0.2f, 0}, {1.00f, 0.00f, 0, 0});
  const int b2 = s.add(1, {3.3f, -0.2f, 0}, {1.00f, 0.02f, 0, 0});
  // Another class elsewhere in the scene sets the descriptor scale.
  s.add(0, {-8, 4, 0}, table);
  s.add(1, {-8, 4.5f, 0}, table);
  const Matches m = run_stage(s);
  EXPECT_EQ(m.find(a1)->match, b1);
  EXPECT_EQ(m.find(a2)->match, b2);
  EXPECT_EQ(m.find(b2)->match, a2);
  // Only chairs: the physical term still wins when it has the larger weight.
  Scene only;
  only.objects.missions = {"A", "B"};
  only.add(0, {0, 0, 0}, {1.00f, 0.02f, 0, 0});
  only.add(0, {3, 0, 0}, {1.00f, 0.00f, 0, 0});
  only.add(1, {0.4f, 0.2f, 0}, {1.00f, 0.00f, 0, 0});
  only.add(1, {3.3f, -0.2f, 0}, {1.00f, 0.02f, 0, 0});
  const Matches o = run_stage(only, {{"alpha", 0.7}, {"beta", 0.3}});
  EXPECT_EQ(o.find(0)->match, 2);
  EXPECT_EQ(o.find(1)->match, 3);
}

TEST(MatchWeighted, PhysicalGateKeepsFarChangesApart) {
  Scene s;
  s.objects.missions = {"A", "B"};
  const int a = s.add(0, {0, 0, 0}, chair);
  const int b = s.add(1, {20, 0, 0}, chair);
  Matches m = run_stage(s, {{"max_distance", 5.0}});
  EXPECT_EQ(m.find(a)->status, ChangeStatus::removed);
  EXPECT_EQ(m.find(b)->status, ChangeStatus::added);
  m = run_stage(s);  // default gate 30 m: across a room is a move
  EXPECT_EQ(m.find(a)->status, ChangeStatus::moved);
  EXPECT_EQ(m.find(a)->match, b);
}

TEST(MatchWeighted, SizeGateKeepsUnlikeSizesApart) {
  // Same descriptor, 1 m apart, but one is 0.5 m tall and the other 1.5 m:
  // no rigid object changes its height by moving.
  Scene s;
  s.objects.missions = {"A", "B"};
  const int a = s.add(0, {0, 0, 0}, chair, {0.5f, 0.5f, 0.5f});
  const int b = s.add(1, {1, 0, 0}, chair, {0.5f, 0.5f, 1.5f});
  const int c = s.add(1, {4, 0, 0}, chair, {0.55f, 0.5f, 0.45f});
  Matches m = run_stage(s);
  EXPECT_EQ(m.find(a)->match, c);
  EXPECT_EQ(m.find(b)->status, ChangeStatus::added);
  m = run_stage(s, {{"max_size_change", 0.0}});  // gate off: the nearer one wins
  EXPECT_EQ(m.find(a)->match, b);
}

TEST(MatchWeighted, WeightedGateAndGroups) {
  Scene s;
  s.objects.missions = {"A", "B"};
  const int a = s.add(0, {0, 0, 0}, chair);
  const int b = s.add(1, {1, 0, 0}, table);
  Groups g;
  g.object_ids = {a, b};
  g.group = {0, 1};
  g.confidence = {1, 1};
  g.group_confidence = {1, 1};
  g.count = 2;
  // Soft: the cross-group penalty pushes the only pair over the default gate.
  EXPECT_EQ(run_stage(s, {}, &g).find(a)->status, ChangeStatus::removed);
  // Without the penalty it is the only candidate and is taken.
  EXPECT_EQ(run_stage(s, {{"group_penalty", 0.0}}, &g).find(a)->status, ChangeStatus::moved);
  // Hard forbids it whatever the penalty; ignore drops groups.
  EXPECT_EQ(run_stage(s, {{"group_mode", std::string("hard")}, {"group_penalty", 0.0}}, &g).find(a)->status,
            ChangeStatus::removed);
  EXPECT_EQ(run_stage(s, {{"group_mode", std::string("ignore")}}, &g).find(a)->status, ChangeStatus::moved);
  // Descriptor gate in descriptor units: chair vs table are sqrt(2) apart.
  EXPECT_EQ(run_stage(s, {{"max_descriptor_distance", 1.0}}).find(a)->status, ChangeStatus::removed);
}

TEST(MatchWeighted, HistoryAcrossThreeMissions) {
  Scene s;
  s.objects.missions = {"A", "B", "C"};
  const int a = s.add(0, {0, 0, 0}, chair);
  const int b = s.add(1, {1, 0, 0}, chair);
  const int c = s.add(2, {2, 0, 0}, chair);
  const int gone = s.add(1, {-3, 3, 0}, table);  // only in B: gone by C
  const Matches m = run_stage(s);
  const std::vector<int> chain{a, b, c};
  EXPECT_EQ(m.find(a)->history, chain);
  EXPECT_EQ(m.find(b)->history, chain);
  EXPECT_EQ(m.find(c)->history, chain);
  EXPECT_EQ(m.find(a)->match, b);
  EXPECT_EQ(m.find(b)->match, c);  // the next mission's partner first
  EXPECT_EQ(m.find(c)->match, b);
  EXPECT_EQ(m.find(gone)->status, ChangeStatus::removed);
}

TEST(MatchWeighted, BadInputIsAnError) {
  Scene s;
  s.objects.missions = {"A"};
  s.add(3, {0, 0, 0}, chair);
  EXPECT_THROW(run_stage(s), Error);
  EXPECT_THROW(stage_test::make_stage("match.weighted", {{"alpha", 0.0}, {"beta", 0.0}}), Error);
}
