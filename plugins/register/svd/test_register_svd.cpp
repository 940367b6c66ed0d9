#include <lista_testing/plugin_stage.hpp>
#include <lista_objreg/svd_registration.hpp>

#include <lista/basic_context.hpp>

#include <gtest/gtest.h>
#include <random>

using namespace lista;
using namespace lista::objreg;

namespace {

// An asymmetric "chair": a seat, a back on one side and one leg, so every
// principal axis has a clear skew.
std::vector<Eigen::Vector3f> chair_points(uint64_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < 1500; ++i) p.emplace_back(1.0f * u(rng), 0.6f * u(rng), 0.45f);            // seat
  for (int i = 0; i < 900; ++i) p.emplace_back(0.0f, 0.6f * u(rng), 0.45f + 0.5f * u(rng));       // back
  for (int i = 0; i < 300; ++i) p.emplace_back(0.9f, 0.05f, 0.45f * u(rng));                      // leg
  return p;
}

Object make_object(int id, uint32_t mission, const std::vector<Eigen::Vector3f>& pts) {
  Object o;
  o.id = id;
  o.mission = mission;
  for (size_t i = 0; i < pts.size(); ++i) {
    o.points.xyz.push_back(pts[i]);
    o.points.scan.push_back(0);
    o.points.index.push_back(static_cast<uint32_t>(i));
  }
  o.update_geometry();
  return o;
}

ObjectChange change(int id, ChangeStatus status, int match) {
  ObjectChange c;
  c.object_id = id;
  c.status = status;
  c.match = match;
  return c;
}

double angle_deg(const Eigen::Matrix3d& r) {
  return Eigen::AngleAxisd(r).angle() * 180.0 / M_PI;
}

}  // namespace

TEST(SvdRegistration, RecoversKnownRotationAndTranslation) {
  const auto src = chair_points(1);
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.linear() = (Eigen::AngleAxisd(0.9, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX())).toRotationMatrix();
  truth.translation() = Eigen::Vector3d(2.0, -1.0, 0.3);
  std::vector<Eigen::Vector3f> dst;
  for (const auto& p : src) dst.push_back((truth * p.cast<double>()).cast<float>());
  const Eigen::Isometry3d t = svd_transform(principal_frame(src), principal_frame(dst));
  EXPECT_LT((t.translation() - truth.translation()).norm(), 1e-6);
  EXPECT_LT(angle_deg(t.linear().transpose() * truth.linear()), 1e-4);
}

TEST(SvdRegistration, StageFillsInverseTransformsForBothEnds) {
  const auto src = chair_points(2);
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.linear() = Eigen::AngleAxisd(-2.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  truth.translation() = Eigen::Vector3d(1.0, 3.0, 0.0);
  std::vector<Eigen::Vector3f> dst;
  for (const auto& p : src) dst.push_back((truth * p.cast<double>()).cast<float>());
  ObjectSet objects;
  objects.missions = {"A", "B"};
  objects.objects = {make_object(0, 0, src), make_object(1, 1, dst), make_object(2, 0, src)};
  Matches m;
  m.objects.resize(3);
  m.objects[0] = change(0, ChangeStatus::moved, 1);
  m.objects[1] = change(1, ChangeStatus::moved, 0);
  m.objects[2] = change(2, ChangeStatus::removed, -1);
  auto stage = plugin_test::make_stage("register.svd");
  BasicContext ctx("reg", 2);
  Inputs in;
  in.set("objects", Data::make(objects));
  in.set("matches", Data::make(m));
  const Matches out = stage->run(in, ctx).at("matches").as<Matches>();
  ASSERT_TRUE(out.find(0)->has_transform);
  ASSERT_TRUE(out.find(1)->has_transform);
  EXPECT_FALSE(out.find(2)->has_transform);
  EXPECT_TRUE(out.find(0)->transform.isApprox(truth.matrix(), 1e-5));
  EXPECT_TRUE((out.find(0)->transform * out.find(1)->transform).isIdentity(1e-9));
}

TEST(SvdRegistration, FlagsSymmetricShapesAndRejectsEmpty) {
  // A symmetric box: no skew along any axis.
  std::vector<Eigen::Vector3f> box;
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 6; ++y)
      for (int z = 0; z < 3; ++z) box.emplace_back(x * 0.2f, y * 0.1f, z * 0.1f);
  EXPECT_TRUE(principal_frame(box).ambiguous_sign);
  EXPECT_FALSE(principal_frame(chair_points(3)).ambiguous_sign);
  EXPECT_THROW(principal_frame({}), Error);
}

TEST(SvdRegistration, MatchesNamingUnknownObjectsAreAnError) {
  ObjectSet objects;
  objects.missions = {"A", "B"};
  objects.objects = {make_object(0, 0, chair_points(4))};
  Matches m;
  m.objects = {change(0, ChangeStatus::moved, 7)};
  auto stage = plugin_test::make_stage("register.svd");
  BasicContext ctx;
  Inputs in;
  in.set("objects", Data::make(objects));
  in.set("matches", Data::make(m));
  EXPECT_THROW(stage->run(in, ctx), Error);
}
