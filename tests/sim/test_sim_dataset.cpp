// Generates the `tiny` preset with the real lista-sim binary and checks it
// against the data contract through lista_io's readers.
#include <lista_io/dataset.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/report.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace lista;

namespace {

fs::path temp_root() {
  static const fs::path root = [] {
    fs::path p = fs::temp_directory_path() / ("lista_sim_test_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return root;
}

// Runs lista-sim; returns its exit status.
int simulate(const std::string& args) {
  const std::string cmd = std::string(LISTA_BIN_DIR) + "/lista-sim " + args + " > /dev/null 2>&1";
  return std::system(cmd.c_str());
}

const fs::path& tiny() {
  static const fs::path dir = [] {
    const fs::path d = temp_root() / "tiny";
    EXPECT_EQ(simulate("--preset tiny --seed 7 --threads 2 --out " + d.string()), 0);
    return d;
  }();
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A views folder's index.json.
nlohmann::json views_index(const fs::path& dir) { return nlohmann::json::parse(slurp(dir / "index.json")); }

std::map<std::string, std::string> all_files(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files[fs::relative(e.path(), root).string()] = slurp(e.path());
  return files;
}

// Removes the generated datasets after the suite.
class TempCleanup : public ::testing::Environment {
 public:
  void TearDown() override { fs::remove_all(temp_root()); }
};
const auto* const cleanup = ::testing::AddGlobalTestEnvironment(new TempCleanup);

bool differs(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  const Eigen::Matrix3d r = a.topLeftCorner<3, 3>().transpose() * b.topLeftCorner<3, 3>();
  const double angle = std::acos(std::clamp((r.trace() - 1.0) / 2.0, -1.0, 1.0));
  return (a.topRightCorner<3, 1>() - b.topRightCorner<3, 1>()).norm() > 0.05 || angle > 5.0 * M_PI / 180.0;
}

}  // namespace

TEST(SimDataset, ReadsBackWithPosesAndLabels) {
  const MissionSet set = io::read_dataset(tiny().string());
  ASSERT_EQ(set.missions.size(), 2u);
  EXPECT_EQ(set.missions[0].name, "A");
  EXPECT_EQ(set.missions[1].name, "B");
  for (const auto& m : set.missions) {
    ASSERT_EQ(m.scans.size(), 10u);
    ASSERT_EQ(m.poses_gt.size(), m.scans.size());
    std::set<uint32_t> labels;
    size_t points = 0;
    for (const auto& s : m.scans) {
      ASSERT_TRUE(s.points->has_label());
      ASSERT_TRUE(s.points->has_intensity());
      points += s.points->size();
      labels.insert(s.points->label.begin(), s.points->label.end());
      for (float v : s.points->intensity) ASSERT_TRUE(v >= 0.0f && v <= 255.0f);
    }
    EXPECT_GT(points, 10000u);
    EXPECT_TRUE(labels.count(0));  // structure
    EXPECT_GE(labels.size(), 5u);  // and several objects
  }
}

TEST(SimDataset, GroundTruthHasEveryKindOfChange) {
  const io::GroundTruth gt = io::read_ground_truth((tiny() / "ground_truth.json").string());
  ASSERT_EQ(gt.missions, (std::vector<std::string>{"A", "B"}));
  int moved = 0, removed = 0, added = 0, dynamic = 0;
  std::set<int> ids;
  for (const auto& o : gt.objects) {
    EXPECT_TRUE(ids.insert(o.id).second);
    EXPECT_NE(o.id, 0);
    if (o.dynamic) {
      ++dynamic;
      continue;
    }
    const auto& a = o.poses.at("A");
    const auto& b = o.poses.at("B");
    if (a && !b) ++removed;
    if (!a && b) ++added;
    if (a && b && differs(*a, *b)) ++moved;
  }
  EXPECT_GE(moved, 2);
  EXPECT_GE(removed, 1);
  EXPECT_GE(added, 1);
  EXPECT_GE(dynamic, 1);
}

TEST(SimDataset, LabelledPointsLieOnTheirObjects) {
  const MissionSet set = io::read_dataset(tiny().string());
  const io::GroundTruth gt = io::read_ground_truth((tiny() / "ground_truth.json").string());
  std::map<int, const io::TruthObject*> by_id;
  for (const auto& o : gt.objects) by_id[o.id] = &o;
  size_t checked = 0, people = 0;
  for (const auto& m : set.missions)
    for (size_t i = 0; i < m.scans.size(); ++i) {
      const auto& pts = *m.scans[i].points;
      for (size_t k = 0; k < pts.size(); k += 7) {
        const uint32_t label = pts.label[k];
        if (label == 0) continue;
        ASSERT_TRUE(by_id.count(int(label))) << "label " << label << " not in the ground truth";
        const auto* o = by_id[int(label)];
        if (o->dynamic) {
          ++people;
          continue;
        }
        ASSERT_TRUE(o->poses.at(m.name).has_value()) << "object " << label << " seen in " << m.name << " but absent";
        // Into the object's own frame: it stands on z = 0, centred, a few metres at most.
        const Eigen::Vector3d world = m.poses_gt[i] * pts.xyz[k].cast<double>();
        const Eigen::Matrix4d pose = *o->poses.at(m.name);
        const Eigen::Vector3d local =
            pose.topLeftCorner<3, 3>().transpose() * (world - pose.topRightCorner<3, 1>());
        EXPECT_GT(local.z(), -0.1);
        EXPECT_LT(local.z(), 2.5);
        EXPECT_LT(local.head<2>().norm(), 1.6);
        ++checked;
      }
    }
  EXPECT_GT(checked, 100u);
  EXPECT_GT(people, 10u) << "the people walking through the missions are in no scan";
}

TEST(SimDataset, OdometryDriftsButStaysBounded) {
  const MissionSet set = io::read_dataset(tiny().string());
  const io::GroundTruth gt = io::read_ground_truth((tiny() / "ground_truth.json").string());
  for (const auto& m : set.missions) {
    // mission_to_world maps the first estimated pose exactly onto the truth.
    const Eigen::Isometry3d to_world(gt.mission_to_world.at(m.name));
    EXPECT_LT(((to_world * m.scans[0].pose).matrix() - m.poses_gt[0].matrix()).norm(), 1e-4);
    // After aligning the first poses, the rest differ by the drift.
    const Eigen::Isometry3d align = m.poses_gt[0] * m.scans[0].pose.inverse();
    double worst = 0.0;
    for (size_t i = 0; i < m.scans.size(); ++i)
      worst = std::max(worst, ((align * m.scans[i].pose).translation() - m.poses_gt[i].translation()).norm());
    EXPECT_GT(worst, 1e-3) << m.name;
    EXPECT_LT(worst, 1.0) << m.name;
  }
  // Each mission has its own map frame.
  EXPECT_TRUE(differs(gt.mission_to_world.at("A"), gt.mission_to_world.at("B")));
}

TEST(SimDataset, RouteIsRepeatedWithinTwentyCentimetres) {
  const MissionSet set = io::read_dataset(tiny().string());
  const auto& first = set.missions[0].poses_gt;
  // The route is sampled at different places per mission: compare against
  // the first mission's path, densified by linear interpolation.
  for (const auto& pose : set.missions[1].poses_gt) {
    double best = 1e9;
    for (size_t i = 0; i < first.size(); ++i) {
      const Eigen::Vector3d a = first[i].translation(), b = first[(i + 1) % first.size()].translation();
      for (int k = 0; k <= 50; ++k) best = std::min(best, (a + (b - a) * (k / 50.0) - pose.translation()).norm());
    }
    EXPECT_LT(best, 0.25);
  }
}

TEST(SimDataset, SameSeedSameBytesWhateverTheThreads) {
  const fs::path a = temp_root() / "det_a", b = temp_root() / "det_b", c = temp_root() / "det_c";
  ASSERT_EQ(simulate("--preset tiny --seed 3 --threads 1 --out " + a.string()), 0);
  ASSERT_EQ(simulate("--preset tiny --seed 3 --threads 2 --out " + b.string()), 0);
  ASSERT_EQ(simulate("--preset tiny --seed 4 --threads 2 --out " + c.string()), 0);
  const auto fa = all_files(a), fb = all_files(b), fc = all_files(c);
  ASSERT_GT(fa.size(), 20u);
  EXPECT_TRUE(fa == fb);
  EXPECT_FALSE(fa == fc);
}

TEST(SimDataset, RefusesToOverwriteAndRejectsBadInput) {
  EXPECT_NE(simulate("--preset tiny --out " + tiny().string()), 0);  // exists
  EXPECT_NE(simulate("--preset nosuch --out " + (temp_root() / "x").string()), 0);
  EXPECT_NE(simulate("--preset tiny --sensor nosuch --out " + (temp_root() / "y").string()), 0);
  EXPECT_EQ(simulate("--preset tiny --missions 3 --scans 4 --overwrite --out " + (temp_root() / "three").string()), 0);
  EXPECT_EQ(io::read_dataset((temp_root() / "three").string()).missions.size(), 3u);
}

TEST(SimDataset, ViewsModeWritesIndexAndClouds) {
  const fs::path dir = temp_root() / "views";
  ASSERT_EQ(simulate("views --objects 6 --views-per-object 2 --seed 5 --out " + dir.string()), 0);
  const std::string index = slurp(dir / "index.json");
  EXPECT_NE(index.find("\"lista-views/1\""), std::string::npos);
  size_t clouds = 0;
  for (const auto& e : fs::directory_iterator(dir / "views")) {
    const io::ScanFile f = io::read_scan(e.path().string());
    EXPECT_GE(f.points.size(), 1u);
    ++clouds;
  }
  EXPECT_EQ(clouds, 12u);
}

// Look-alikes share one shape id by default; --look-alike-tolerance 0 keeps
// them apart (then shape == variant). The same views either way, each
// keeping its distinct mesh's id as variant, and one variant is one shape.
TEST(SimDataset, ViewsGiveLookAlikesOneShapeId) {
  const fs::path merged = temp_root() / "views-merged", strict = temp_root() / "views-strict";
  const std::string common = "views --objects 300 --views-per-object 1 --seed 3 --out ";
  ASSERT_EQ(simulate(common + merged.string()), 0);
  ASSERT_EQ(simulate(common + strict.string() + " --look-alike-tolerance 0"), 0);
  const nlohmann::json m = views_index(merged), s = views_index(strict);
  EXPECT_DOUBLE_EQ(m.at("look_alike_tolerance").get<double>(), 0.02);
  EXPECT_DOUBLE_EQ(s.at("look_alike_tolerance").get<double>(), 0.0);
  ASSERT_EQ(m.at("views").size(), s.at("views").size());
  std::map<std::string, std::string> shape_of_variant;
  std::set<std::string> merged_shapes, strict_shapes;
  for (size_t i = 0; i < m.at("views").size(); ++i) {
    const auto &a = m["views"][i], &b = s["views"][i];
    EXPECT_EQ(a.at("variant"), b.at("variant"));
    EXPECT_EQ(a.at("points"), b.at("points"));
    EXPECT_EQ(b.at("shape"), b.at("variant"));  // tolerance 0: every distinct mesh its own id
    const auto [it, fresh] = shape_of_variant.emplace(a.at("variant"), a.at("shape"));
    if (!fresh) {
      EXPECT_EQ(it->second, a.at("shape").get<std::string>());
    }
    merged_shapes.insert(a.at("shape"));
    strict_shapes.insert(b.at("shape"));
  }
  EXPECT_LT(merged_shapes.size(), strict_shapes.size()) << "300 objects hold look-alike barrels and tanks";
  EXPECT_NE(simulate("views --objects 2 --look-alike-tolerance -1 --out " + (temp_root() / "views-neg").string()), 0);
}

// No shapes to draw from is an error that leaves the folder's views alone,
// --overwrite or not; so are a furniture folder without a catalogue and one
// without a usable model.
TEST(SimDataset, ViewsWithoutShapesFailAndKeepOldViews) {
  const fs::path dir = temp_root() / "views-kept";
  ASSERT_EQ(simulate("views --objects 2 --views-per-object 1 --seed 5 --out " + dir.string()), 0);
  const std::string index = slurp(dir / "index.json");
  EXPECT_NE(simulate("views --objects 2 --no-procedural --overwrite --out " + dir.string()), 0);
  EXPECT_NE(simulate("views --objects 2 --furniture " + (temp_root() / "no-such-shapes").string() +
                     " --overwrite --out " + dir.string()),
            0);
  // A catalogue whose only entry is a door gives no usable shape.
  const fs::path doors = temp_root() / "doors-only";
  fs::create_directories(doors);
  std::ofstream(doors / "PluginFurnitureCatalog.properties")
      << "id#1=door\nmodel#1=/door.obj\nwidth#1=90\ndepth#1=5\nheight#1=200\ndoorOrWindow#1=true\n";
  EXPECT_NE(simulate("views --objects 2 --no-procedural --furniture " + doors.string() + " --overwrite --out " +
                     dir.string()),
            0);
  EXPECT_EQ(slurp(dir / "index.json"), index);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "views"), fs::directory_iterator{}), 2);
}

// --sensors swaps the sensors and nothing else: the same shapes, viewpoints
// and splits as the default draw, every view from a listed sensor. An
// unknown one fails before the folder's old views are touched.
TEST(SimDataset, ViewsFromOtherSensorsKeepShapesAndViewpoints) {
  const fs::path usual = temp_root() / "views-usual", other = temp_root() / "views-other";
  const std::string common = "views --objects 5 --views-per-object 3 --seed 8 --out ";
  ASSERT_EQ(simulate(common + usual.string()), 0);
  ASSERT_EQ(simulate(common + other.string() + " --sensors os1-64,hdl32"), 0);
  const nlohmann::json a = views_index(usual), b = views_index(other);
  ASSERT_EQ(a.at("views").size(), b.at("views").size());
  std::set<std::string> sensors;
  for (size_t i = 0; i < a.at("views").size(); ++i) {
    const auto &u = a["views"][i], &o = b["views"][i];
    EXPECT_EQ(u.at("shape"), o.at("shape"));
    EXPECT_EQ(u.at("split"), o.at("split"));
    if (u.at("viewpoint") != o.at("viewpoint")) continue;  // a retried view (too few points) may differ
    EXPECT_NE(u.at("sensor"), o.at("sensor"));
    sensors.insert(o.at("sensor").get<std::string>());
  }
  EXPECT_EQ(sensors, (std::set<std::string>{"os1-64", "hdl32"}));
  const std::string index = slurp(other / "index.json");
  EXPECT_NE(simulate(common + other.string() + " --overwrite --sensors os1-64,lidar9000"), 0);
  EXPECT_EQ(slurp(other / "index.json"), index);
}

// Multi-sweep views merge sweeps along a pass: same objects and splits, more
// of each object seen.
TEST(SimDataset, ViewsMergeSweepsAlongAPass) {
  const fs::path one = temp_root() / "views-one", pass = temp_root() / "views-pass";
  ASSERT_EQ(simulate("views --objects 4 --views-per-object 3 --seed 6 --out " + one.string()), 0);
  ASSERT_EQ(simulate("views --objects 4 --views-per-object 3 --seed 6 --scans-per-view 4 --out " + pass.string()), 0);
  EXPECT_NE(slurp(pass / "index.json").find("\"scans\": 4"), std::string::npos);
  auto points_in = [](const fs::path& dir) {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir / "views")) n += io::read_scan(e.path().string()).points.size();
    return n;
  };
  EXPECT_GT(points_in(pass), 2 * points_in(one));
  EXPECT_NE(simulate("views --objects 4 --scans-per-view 0 --out " + (temp_root() / "views-zero").string()), 0);
}

// --furniture places Sweet Home 3D models in a mission scene beside the
// procedural classes (here a one-desk catalogue); a folder without a
// catalogue fails before any dataset is written.
TEST(SimDataset, MissionScenesPlaceCatalogueFurniture) {
  const fs::path shapes = temp_root() / "desk-catalogue";
  fs::create_directories(shapes / "desk");
  std::ofstream(shapes / "desk" / "desk.obj") << "v 0 0 0\nv 200 0 0\nv 200 0 80\nv 0 0 80\n"
                                                 "v 0 75 0\nv 200 75 0\nv 200 75 80\nv 0 75 80\n"
                                                 "f 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  std::ofstream(shapes / "PluginFurnitureCatalog.properties")
      << "id#1=Test#desk\nname#1=Desk\ncategory#1=Office\nmodel#1=/desk/desk.obj\nwidth#1=150\ndepth#1=70\n"
         "height#1=75\n";
  const fs::path dir = temp_root() / "tiny-furniture";
  ASSERT_EQ(simulate("--preset tiny --seed 4 --scans 4 --threads 2 --furniture " + shapes.string() + " --out " +
                     dir.string()),
            0);
  const auto truth = nlohmann::json::parse(slurp(dir / "ground_truth.json"));
  int desks = 0, procedural = 0;
  for (const auto& o : truth["objects"]) {
    if (o["dynamic"].get<bool>()) continue;
    (o["class"] == "sh3d/office" ? desks : procedural) += 1;
  }
  EXPECT_GT(desks, 0) << "a third of the objects are drawn from the catalogue";
  EXPECT_GT(procedural, desks);
  const fs::path none = temp_root() / "tiny-no-furniture";
  EXPECT_NE(simulate("--preset tiny --furniture " + (temp_root() / "no-such-shapes").string() + " --out " +
                     none.string()),
            0);
  EXPECT_FALSE(fs::exists(none));
}
