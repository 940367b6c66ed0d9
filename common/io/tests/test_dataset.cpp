#include "test_util.hpp"

#include <fstream>
#include <lista_io/dataset.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>

#include <algorithm>
#include <cmath>

using namespace lista;
using namespace lista::io;
using namespace lista_io_test;
namespace fs = std::filesystem;

namespace {

PointSet scan_points(int scan, size_t n) {
  PointSet p;
  for (size_t i = 0; i < n; ++i) {
    p.xyz.emplace_back(float(scan), float(i), 1.f);
    p.intensity.push_back(0.5f);
    p.label.push_back(uint32_t(i % 3));
  }
  if (n > 1) p.xyz[1].x() = NAN;  // one non-finite point per scan
  return p;
}

// A mission folder with `scans` scans of `n` points, in the given encoding.
void make_mission(const fs::path& dir, int scans, size_t n, bool with_gt = false) {
  fs::create_directories(dir / "scans");
  std::vector<PoseRecord> poses;
  for (int s = 0; s < scans; ++s) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.pcd", s);
    write_scan_pcd((dir / "scans" / name).string(), scan_points(s, n),
                   s % 2 ? PcdEncoding::binary_compressed : PcdEncoding::binary);
    PoseRecord r;
    r.timestamp = s;
    r.pose.translation() = Eigen::Vector3d(s, 0, 0);
    poses.push_back(r);
  }
  write_poses((dir / "poses.txt").string(), poses);
  if (with_gt) {
    for (auto& r : poses) r.pose.translation().y() += 10;
    write_poses((dir / "poses_gt.txt").string(), poses, PoseFormat::kitti);
  }
}

}  // namespace

TEST(Dataset, ReadsMissionsSortedWithProvenanceInParallel) {
  const auto root = temp_dir("ds");
  make_mission(root / "b_second", 3, 10, true);
  make_mission(root / "a_first", 4, 5);
  fs::create_directories(root / "notes");  // not a mission: ignored
  EXPECT_EQ(list_missions(root.string()), (std::vector<std::string>{"a_first", "b_second"}));
  // macOS metadata beside a copied scan is not a scan (the counts still agree).
  std::ofstream(root / "a_first" / "scans" / "._000001.pcd") << "junk";
  DatasetOptions opt;
  opt.threads = 3;
  const MissionSet set = read_dataset(root.string(), opt);
  ASSERT_EQ(set.missions.size(), 2u);
  const Mission& a = set.missions[0];
  EXPECT_EQ(a.name, "a_first");
  ASSERT_EQ(a.scans.size(), 4u);
  EXPECT_EQ(a.skipped_nonfinite, 4u);
  EXPECT_TRUE(a.poses_gt.empty());
  for (size_t s = 0; s < 4; ++s) {
    const PointSet& p = *a.scans[s].points;
    EXPECT_EQ(a.scans[s].points_in_file, 5u);
    ASSERT_EQ(p.size(), 4u);
    EXPECT_EQ(p.scan[0], s);
    EXPECT_EQ(p.index[1], 2u);  // index 1 was the non-finite point
    EXPECT_EQ(p.xyz[0].x(), float(s));
    EXPECT_EQ(a.scans[s].pose.translation().x(), double(s));
  }
  const Mission& b = set.missions[1];
  ASSERT_EQ(b.poses_gt.size(), 3u);
  EXPECT_DOUBLE_EQ(b.poses_gt[2].translation().y(), 10.0);
  EXPECT_EQ(b.point_count(), 27u);

  DatasetOptions only;
  only.missions = {"b_second"};
  only.load_points = false;
  const MissionSet one = read_dataset(root.string(), only);
  ASSERT_EQ(one.missions.size(), 1u);
  EXPECT_EQ(one.missions[0].name, "b_second");
  EXPECT_EQ(one.missions[0].scans[0].points->size(), 0u);
}

// A dense log thinned on reading: scans 1 m apart, one read every 2 m (and
// the last); the others keep their pose, hold no points and count none.
TEST(Dataset, ScanSpacingReadsAScanEverySoManyMetres) {
  const auto root = temp_dir("ds");
  make_mission(root / "m", 6, 4);
  DatasetOptions opt;
  opt.scan_spacing = 2.0;
  opt.threads = 2;
  const Mission m = read_dataset(root.string(), opt).missions.at(0);
  ASSERT_EQ(m.scans.size(), 6u);
  for (size_t s = 0; s < 6; ++s) {
    const bool read = s == 0 || s == 2 || s == 4 || s == 5;
    EXPECT_EQ(m.scans[s].points->empty(), !read) << s;
    EXPECT_EQ(m.scans[s].points_in_file, read ? 4u : 0u) << s;
    EXPECT_EQ(m.scans[s].pose.translation().x(), double(s));
  }
  // A turn on the spot is read too; a spacing of 0 reads everything.
  std::vector<Eigen::Isometry3d> poses(4, Eigen::Isometry3d::Identity());
  poses[1].linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  poses[2].linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  poses[3].linear() = Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_EQ(scans_to_read(poses, 1.0, 30.0), (std::vector<char>{1, 0, 1, 1}));
  EXPECT_EQ(scans_to_read(poses, 0.0, 30.0), (std::vector<char>{1, 1, 1, 1}));
}

// A dense log is thinned at dense_spacing only when scan_spacing is unset;
// a short one, or one of scans farther apart, is read whole.
TEST(Dataset, DenseSpacingAppliesToDenseLogsOnly) {
  auto line = [](size_t n, double step) {
    std::vector<Eigen::Isometry3d> poses(n, Eigen::Isometry3d::Identity());
    for (size_t i = 0; i < n; ++i) poses[i].translation().x() = step * double(i);
    return poses;
  };
  DatasetOptions opt;
  opt.dense_spacing = 0.5;
  EXPECT_NEAR(median_step(line(kDenseLogScans, 0.05)), 0.05, 1e-9);
  EXPECT_EQ(spacing_for(line(kDenseLogScans, 0.05), opt), 0.5);
  EXPECT_EQ(spacing_for(line(kDenseLogScans - 1, 0.05), opt), 0.0);
  EXPECT_EQ(spacing_for(line(kDenseLogScans, kDenseLogStep + 0.01), opt), 0.0);
  // Standing still counts: every step is 0.
  EXPECT_EQ(spacing_for(line(kDenseLogScans, 0.0), opt), 0.5);
  opt.scan_spacing = 2.0;
  EXPECT_EQ(spacing_for(line(10, 1.0), opt), 2.0);
  opt.scan_spacing = 0.0;
  opt.dense_spacing = 0.0;
  EXPECT_EQ(spacing_for(line(kDenseLogScans, 0.05), opt), 0.0);
}

// The VIEWPOINT layout's poses are in the files' headers: only the headers
// of the scans left out are read.
TEST(Dataset, ScanSpacingThinsTheViewpointLayoutToo) {
  const auto root = temp_dir("vp_thin");
  std::vector<float> x = {1.f}, y = {0.f}, z = {0.f};
  for (int s = 0; s < 4; ++s) {
    Eigen::Isometry3d vp = Eigen::Isometry3d::Identity();
    vp.translation() = Eigen::Vector3d(0.6 * s, 0, 0);
    char name[32];
    std::snprintf(name, sizeof name, "%03d.pcd", s);
    write_pcd((root / name).string(), 1, {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()}},
              PcdEncoding::binary, vp);
    // The scan to be skipped has a broken payload: only its header may be read.
    if (s == 1) fs::resize_file(root / name, fs::file_size(root / name) - 6);
  }
  EXPECT_THROW(read_dataset(root.string(), DatasetOptions{}), Error) << "the premise: scan 1 cannot be read whole";
  DatasetOptions opt;
  opt.scan_spacing = 1.0;
  const Mission m = read_dataset(root.string(), opt).missions.at(0);
  ASSERT_EQ(m.scans.size(), 4u);
  // 0 m, 0.6 m (skipped), 1.2 m, 1.8 m (the last, always read).
  EXPECT_EQ(m.scans[0].points->size(), 1u);
  EXPECT_TRUE(m.scans[1].points->empty());
  EXPECT_EQ(m.scans[1].points_in_file, 0u);
  EXPECT_NEAR(m.scans[1].pose.translation().x(), 0.6, 1e-9);
  EXPECT_EQ(m.scans[2].points->size(), 1u);
  EXPECT_EQ(m.scans[3].points->size(), 1u);
}

// A scan of the VIEWPOINT layout whose header never ends (no DATA line) is
// an error naming the file, also when the mission is thinned from headers.
TEST(Dataset, AViewpointScanWithoutAHeaderIsAnErrorWhenThinned) {
  const auto root = temp_dir("vp_bad_header");
  std::vector<float> x = {1.f}, y = {0.f}, z = {0.f};
  for (int s = 0; s < 3; ++s) {
    char name[32];
    std::snprintf(name, sizeof name, "%03d.pcd", s);
    write_pcd((root / name).string(), 1, {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()}});
  }
  std::ofstream(root / "001.pcd") << "VERSION .7\nFIELDS x y z\n";
  DatasetOptions opt;
  opt.scan_spacing = 1.0;
  try {
    read_dataset(root.string(), opt);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("001.pcd: not a PCD file (no DATA line in the header)"), std::string::npos)
        << e.what();
  }
}

TEST(Dataset, ErrorsAreClear) {
  const auto root = temp_dir("ds");
  make_mission(root / "m", 3, 4);
  fs::remove(root / "m" / "scans" / "000002.pcd");
  expect_error([&] { read_mission((root / "m").string()); }, "2 scan files in scans/ but 3 poses in poses.txt");
  fs::create_directories(root / "empty" / "scans");
  write_text(root / "empty" / "poses.txt", "# nothing\n");
  expect_error([&] { read_mission((root / "empty").string()); }, "empty mission");
  expect_error([&] { read_dataset(root.string(), DatasetOptions{{"nope"}}); }, "no mission 'nope'");
  const auto none = temp_dir("ds_none");
  expect_error([&] { list_missions(none.string()); }, "no missions");
  expect_error([&] { list_missions((none / "absent").string()); }, "does not exist");
  make_mission(root / "g", 2, 4, true);
  write_text(root / "g" / "poses_gt.txt", "0 0 0 0 0 0 0 1\n");
  expect_error([&] { read_mission((root / "g").string()); }, "poses_gt.txt: 1 poses for 2 scans");
  make_mission(root / "bad", 1, 4);
  write_text(root / "bad" / "scans" / "000000.pcd", "FIELDS x\n");
  expect_error([&] { read_mission((root / "bad").string(), DatasetOptions{{}, true, 2}); }, "000000.pcd");
}

TEST(Dataset, ViewpointLayoutPutsPointsInSensorFrame) {
  const auto root = temp_dir("vp");
  Eigen::Isometry3d vp = Eigen::Isometry3d::Identity();
  vp.translate(Eigen::Vector3d(5, 0, 1));
  vp.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  std::vector<float> x = {5.f}, y = {2.f}, z = {1.f};  // map frame: 2 m ahead along map y
  for (const char* name : {"b.pcd", "a.pcd"})
    write_pcd((root / name).string(), 1, {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()}},
              PcdEncoding::binary, vp);
  EXPECT_EQ(list_missions(root.string()), std::vector<std::string>{"."});
  const MissionSet set = read_dataset(root.string());
  ASSERT_EQ(set.missions.size(), 1u);
  const Mission& m = set.missions[0];
  ASSERT_EQ(m.scans.size(), 2u);
  EXPECT_NE(m.scans[0].file.find("a.pcd"), std::string::npos);
  EXPECT_TRUE(m.scans[0].pose.isApprox(vp, 1e-9));
  const Eigen::Vector3f p = m.scans[0].points->xyz[0];
  EXPECT_NEAR(p.x(), 2.f, 1e-5);  // sensor x = map y after the 90 degree yaw
  EXPECT_NEAR(p.y(), 0.f, 1e-5);
  EXPECT_NEAR(p.z(), 0.f, 1e-5);
}

// A georeferenced map frame (UTM): double coordinates keep millimetres only
// if the sensor-frame transform happens before the float conversion; float32
// coordinates that far out lost them in the file, which is an error.
TEST(Dataset, ViewpointLayoutKeepsGeoreferencedDoublesExact) {
  const auto root = temp_dir("vp-utm");
  write_text(root / "a.pcd",
             "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
             "VIEWPOINT 500000 5500000 300 1 0 0 0\nPOINTS 2\nDATA ascii\n"
             "500002.25 5500000.5 301.125\n499999.001 5499999.002 299.003\n");
  const Mission m = read_mission(root.string());
  ASSERT_EQ(m.scans.size(), 1u);
  EXPECT_NEAR(m.scans[0].pose.translation().y(), 5500000.0, 1e-9);
  const auto& xyz = m.scans[0].points->xyz;
  ASSERT_EQ(xyz.size(), 2u);
  EXPECT_NEAR(xyz[0].x(), 2.25f, 1e-6);
  EXPECT_NEAR(xyz[0].y(), 0.5f, 1e-6);
  EXPECT_NEAR(xyz[0].z(), 1.125f, 1e-6);
  EXPECT_NEAR(xyz[1].x(), -0.999f, 1e-5);
  EXPECT_NEAR(xyz[1].y(), -0.998f, 1e-5);
  EXPECT_NEAR(xyz[1].z(), -0.997f, 1e-5);

  const auto f32 = temp_dir("vp-utm-f32");
  Eigen::Isometry3d vp = Eigen::Isometry3d::Identity();
  vp.translate(Eigen::Vector3d(500000, 5500000, 300));
  std::vector<float> x = {500002.f}, y = {5500000.f}, z = {301.f};
  write_pcd((f32 / "a.pcd").string(), 1, {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()}},
            PcdEncoding::binary, vp);
  expect_error([&] { read_mission(f32.string()); }, "a.pcd: map-frame float32 coordinates around a sensor 5500000 m");
}

// Entries named like scans that are no files, a poses.txt that is a folder
// and a mission name that is not UTF-8: each an error naming it.
TEST(Dataset, OddEntriesAreErrorsNamingThem) {
  const auto root = temp_dir("odd");
  make_mission(root / "A", 2, 4);
  fs::remove(root / "A" / "scans" / "000001.pcd");
  fs::create_directory(root / "A" / "scans" / "000001.pcd");
  expect_error([&] { read_mission((root / "A").string()); }, "000001.pcd: is a folder, not a scan file");
  // An extra folder named like a scan is named, not counted against the poses.
  make_mission(root / "A2", 2, 4);
  fs::create_directory(root / "A2" / "scans" / "000002.pcd");
  expect_error([&] { read_mission((root / "A2").string()); }, "000002.pcd: is a folder, not a scan file");
  make_mission(root / "B", 1, 4);
  fs::remove(root / "B" / "poses.txt");
  fs::create_directory(root / "B" / "poses.txt");
  expect_error([&] { read_mission((root / "B").string()); }, "poses.txt: is a folder, not a file");
  // Found by listing the dataset too (it was taken for a VIEWPOINT mission).
  expect_error([&] { read_dataset(root.string(), DatasetOptions{{"B"}, true, 1}); }, "poses.txt: is a folder");
  const std::vector<std::string> listed = list_missions(root.string());
  EXPECT_NE(std::find(listed.begin(), listed.end(), "B"), listed.end()) << "B is a mission (its poses.txt is wrong)";
  make_mission(root / "C\xe9", 1, 4);
  expect_error([&] { read_dataset(root.string(), DatasetOptions{{"C\xe9"}, true, 1}); },
               "mission folder name 'C\\xE9' is not UTF-8");
  // A pipe, a device and a loop of links named like scans; a loop as scans/.
  for (const char* name : {"D", "E", "F", "G"}) make_mission(root / name, 1, 4);
  const fs::path d_scan = root / "D" / "scans" / "000000.pcd", e_scan = root / "E" / "scans" / "000000.pcd";
  fs::remove(d_scan);
  ASSERT_EQ(::mkfifo(d_scan.c_str(), 0600), 0);
  expect_error([&] { read_mission((root / "D").string()); }, "000000.pcd: is a pipe (FIFO), not a scan file");
  fs::remove(e_scan);
  fs::create_symlink("/dev/zero", e_scan);
  expect_error([&] { read_mission((root / "E").string()); }, "000000.pcd: is a device, not a scan file");
  const fs::path f_scan = root / "F" / "scans" / "000000.pcd";
  fs::remove(f_scan);
  fs::create_symlink("000000.pcd", f_scan);
  expect_error([&] { read_mission((root / "F").string()); }, "000000.pcd: is a link to nothing readable");
  fs::remove_all(root / "G" / "scans");
  fs::create_symlink("scans", root / "G" / "scans");
  expect_error([&] { read_mission((root / "G").string()); }, "G/scans: cannot be read (Too many levels of symbolic links)");
}

// What a bag mission folder holds, decided in one place: its .bag files, a
// ROS 2 bag folder (itself or its only subfolder), or one storage file; a
// folder of both kinds, or of several storage files without metadata.yaml,
// is an error; a folder of the data contract holds no recording.
TEST(Dataset, ABagMissionsRecordingIsFoundInOnePlace) {
  const auto root = temp_dir("bags");
  for (const char* m : {"ros1", "ros2", "sub", "file", "both", "two", "plain"}) std::filesystem::create_directories(root / m);
  write_text(root / "ros1" / "b.bag", ""), write_text(root / "ros1" / "a.bag", "");
  write_text(root / "ros2" / "metadata.yaml", "");
  std::filesystem::create_directories(root / "sub" / "rosbag2_1");
  write_text(root / "sub" / "rosbag2_1" / "metadata.yaml", "");
  write_text(root / "file" / "x.mcap", "");
  write_text(root / "both" / "a.bag", ""), write_text(root / "both" / "x.db3", "");
  write_text(root / "two" / "x.db3", ""), write_text(root / "two" / "y.db3", "");
  write_text(root / "plain" / "poses.txt", "");
  EXPECT_EQ(bag_recording((root / "ros1").string()).ros1_files,
            (std::vector<std::string>{(root / "ros1" / "a.bag").string(), (root / "ros1" / "b.bag").string()}));
  EXPECT_EQ(bag_recording((root / "ros2").string()).ros2, (root / "ros2").string());
  EXPECT_EQ(bag_recording((root / "sub").string()).ros2, (root / "sub" / "rosbag2_1").string());
  EXPECT_EQ(bag_recording((root / "file").string()).ros2, (root / "file" / "x.mcap").string());
  expect_error([&] { bag_recording((root / "both").string()); }, "holds both ROS 1 .bag files and a ROS 2 bag");
  expect_error([&] { bag_recording((root / "two").string()); }, "2 ROS 2 storage files and no metadata.yaml");
  EXPECT_FALSE(is_bag_mission((root / "plain").string()));
  EXPECT_TRUE(is_bag_mission((root / "sub").string()));
}
