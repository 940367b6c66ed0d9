#include "test_util.hpp"

#include <lista_io/report.hpp>

#include <Eigen/Geometry>

#include <nlohmann/json.hpp>

using namespace lista::io;
using namespace lista_io_test;

namespace {
Report sample_report() {
  Report r;
  r.missions = {"A", "B"};
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  t(0, 3) = 1.5;
  r.alignment = {{"A", Eigen::Matrix4d::Identity()}, {"B", t}};
  ReportObject o;
  o.id = 3;
  o.mission = "A";
  o.status = "moved";
  o.centroid = {1, 2, 3};
  o.bbox_min = {0, 1, 2};
  o.bbox_max = {2, 3, 4};
  o.points = 1234;
  o.group = 2;
  o.confidence = 0.87;
  o.match = 11;
  o.transform = t;
  Eigen::Matrix4d half_turn = t;  // the same move turned by 180 degrees: a symmetric shape's twin
  half_turn.block<3, 3>(0, 0) = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  o.alternative_transforms = {half_turn};
  o.history = {3, 11};
  o.floor_z = -0.59;
  ReportObject p = o;
  p.id = 11;
  p.mission = "B";
  p.match = 3;
  p.alternative_transforms.clear();
  ReportObject q;
  q.id = 12;
  q.mission = "B";
  q.status = "added";
  r.objects = {o, p, q};
  r.timings_s = {{"read", 1.25}, {"align", 0.5}};
  r.extra_json = R"({"provenance": {"seed": 7}})";
  return r;
}
}  // namespace

TEST(ReportJson, RoundTripAndContractLayout) {
  const auto dir = temp_dir("rep");
  const auto path = (dir / "report.json").string();
  write_report(path, sample_report());
  const Report r = read_report(path);
  ASSERT_EQ(r.objects.size(), 3u);
  EXPECT_EQ(r.objects[1].match, 3);
  EXPECT_EQ(r.objects[2].match, -1);
  EXPECT_FALSE(r.objects[2].transform.has_value());
  EXPECT_DOUBLE_EQ((*r.objects[0].transform)(0, 3), 1.5);
  EXPECT_EQ(r.alignment.at("B")(0, 3), 1.5);
  EXPECT_EQ(r.timings_s[0].first, "read");
  EXPECT_EQ(r.objects[0].history, (std::vector<int>{3, 11}));
  ASSERT_EQ(r.objects[0].alternative_transforms.size(), 1u);
  EXPECT_NEAR(r.objects[0].alternative_transforms[0](0, 0), -1.0, 1e-12);
  EXPECT_TRUE(r.objects[1].alternative_transforms.empty());
  ASSERT_TRUE(r.objects[0].floor_z.has_value());
  EXPECT_DOUBLE_EQ(*r.objects[0].floor_z, -0.59);
  EXPECT_FALSE(r.objects[2].floor_z.has_value());  // unknown: written as null, read back as none
  EXPECT_NE(r.extra_json.find("provenance"), std::string::npos);
  // The raw JSON follows the contract: match null, timings an object.
  std::ifstream in(path);
  const auto j = nlohmann::json::parse(in);
  EXPECT_TRUE(j["objects"][2]["match"].is_null());
  EXPECT_EQ(j["timings_s"]["read"], 1.25);
  EXPECT_EQ(j["provenance"]["seed"], 7);
  EXPECT_EQ(j["alignment"]["B"][0][3], 1.5);
  // Moved objects always carry the list (empty: unambiguous); others never.
  EXPECT_EQ(j["objects"][0]["alternative_transforms"].size(), 1u);
  EXPECT_TRUE(j["objects"][1]["alternative_transforms"].is_array());
  EXPECT_TRUE(j["objects"][1]["alternative_transforms"].empty());
  EXPECT_FALSE(j["objects"][2].contains("alternative_transforms"));
}

TEST(ReportJson, StrictReadingNamesFileAndField) {
  const auto dir = temp_dir("rep");
  const auto path = (dir / "report.json").string();
  write_report(path, sample_report());
  std::ifstream in(path);
  const auto good = nlohmann::json::parse(in);
  auto broken = [&](auto edit, const std::string& needle) {
    auto j = good;
    edit(j);
    write_text(dir / "bad.json", j.dump());
    expect_error([&] { read_report((dir / "bad.json").string()); }, needle);
  };
  broken([](auto& j) { j["objects"][0].erase("centroid"); }, "objects[0]: missing field 'centroid'");
  broken([](auto& j) { j["objects"][1]["mission"] = "C"; }, "unknown mission 'C'");
  broken([](auto& j) { j["objects"][2]["status"] = "gone"; }, "objects[2].status");
  broken([](auto& j) { j["format"] = "lista-report/2"; }, "expected 'lista-report/1'");
  broken([](auto& j) { j["alignment"].erase("B"); }, "alignment: no entry for mission 'B'");
  broken([](auto& j) { j["objects"][0]["points"] = "many"; }, "objects[0].points: must be an integer");
  broken([](auto& j) { j["objects"][0]["points"] = int64_t(1) << 32; }, "objects[0].points: must be an integer");
  broken([](auto& j) { j["objects"][0]["id"] = int64_t(1) << 40; }, "objects[0].id: 1099511627776 is out of range");
  // Matrices must be rigid: an all-zero alignment or a scaled transform is no pose.
  broken([](auto& j) { j["alignment"]["B"] = nlohmann::json::parse("[[0,0,0,0],[0,0,0,0],[0,0,0,0],[0,0,0,0]]"); },
         "alignment.B: is not a rigid transform");
  broken([](auto& j) { j["objects"][0]["transform"][0][0] = 2.0; }, "objects[0].transform: is not a rigid transform");
  broken([](auto& j) { j["objects"][0]["alternative_transforms"][0][1][1] = 3.0; },
         "objects[0].alternative_transforms[0]: is not a rigid transform");
  broken([](auto& j) { j["objects"][0]["alternative_transforms"] = 1; },
         "objects[0].alternative_transforms: expected a list of 4x4 transforms");
  broken([](auto& j) { j["objects"][0]["match"] = 99; }, "names no object id 99");
  broken([](auto& j) { j["objects"][0]["match"] = 3; }, "(id 3).match: names the object itself");
  broken([](auto& j) { j["objects"][1]["match"] = 12; }, "(id 11).match: names object 12 of the same mission 'B'");
  broken([](auto& j) { j["objects"][1]["id"] = 3; }, "duplicate id 3");
  write_text(dir / "text.json", "{ not json");
  expect_error([&] { read_report((dir / "text.json").string()); }, "invalid JSON");
  write_text(dir / "huge.json", "{\"format\": 1e999}");  // nlohmann's out_of_range, not a parse_error
  expect_error([&] { read_report((dir / "huge.json").string()); }, "huge.json: invalid JSON");
  // A transform of null on an object that is not moved is no transform.
  auto with_null = good;
  for (auto& o : with_null["objects"])
    if (o["status"] != "moved") o["transform"] = nullptr;
  write_text(dir / "null.json", with_null.dump());
  const Report r = read_report((dir / "null.json").string());
  for (const auto& o : r.objects) EXPECT_EQ(o.transform.has_value(), o.status == "moved");
  expect_error([&] { read_report((dir / "none.json").string()); }, "none.json: cannot read");
}

TEST(GroundTruthJson, RoundTripAndErrors) {
  const auto dir = temp_dir("gt");
  GroundTruth g;
  g.missions = {"A", "B"};
  g.mission_to_world = {{"A", Eigen::Matrix4d::Identity()}, {"B", Eigen::Matrix4d::Identity()}};
  TruthObject o;
  o.id = 17;
  o.class_name = "chair";
  o.poses = {{"A", Eigen::Matrix4d::Identity()}, {"B", std::nullopt}};
  g.objects = {o};
  const auto path = (dir / "ground_truth.json").string();
  write_ground_truth(path, g);
  const GroundTruth r = read_ground_truth(path);
  ASSERT_EQ(r.objects.size(), 1u);
  EXPECT_EQ(r.objects[0].class_name, "chair");
  EXPECT_TRUE(r.objects[0].poses.at("A").has_value());
  EXPECT_FALSE(r.objects[0].poses.at("B").has_value());
  write_text(dir / "bad.json", R"({"format":"lista-ground-truth/1","missions":["A"],"mission_to_world":{"A":[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]},"objects":[{"id":1,"class":"x","poses":{}}]})");
  expect_error([&] { read_ground_truth((dir / "bad.json").string()); }, "objects[0]: missing field 'dynamic'");
}
