// .db3 bags: written by create_ros2, read back through the folder and
// through the lone file; refusals name the file and the topic.
#include "bag_fixtures.hpp"
#include "cdr.hpp"

#include <lista_bag/ros2.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace lista::bag;
using namespace lista_test;

TEST(Db3, BagRoundTripThroughTheFolder) {
  ScratchDir dir;
  const std::string bag = dir.path("mission");
  {
    auto w = create_ros2(bag, Ros2Storage::sqlite3);
    write_samples(*w);
    EXPECT_FALSE(fs::exists(bag + "/metadata.yaml"));  // before close nothing looks complete
    EXPECT_FALSE(fs::exists(bag + "/mission_0.db3"));
    w->close();
  }
  ASSERT_TRUE(fs::exists(bag + "/metadata.yaml"));
  ASSERT_TRUE(fs::exists(bag + "/mission_0.db3"));
  auto r = open_ros2(bag);
  EXPECT_EQ(r->path(), bag);
  std::map<std::string, TopicInfo> topics;
  for (const TopicInfo& t : r->topics()) topics[t.name] = t;
  ASSERT_EQ(topics.size(), 5u);
  EXPECT_EQ(topics["/points"].type, "sensor_msgs/msg/PointCloud2");
  EXPECT_EQ(topics["/points"].kind, MessageKind::point_cloud);
  EXPECT_EQ(topics["/points"].messages, 2u);
  EXPECT_EQ(topics["/tf"].messages, 2u);
  EXPECT_EQ(topics["/tf_static"].kind, MessageKind::tf_static);
  EXPECT_EQ(topics["/odom"].kind, MessageKind::odometry);
  EXPECT_EQ(topics["/pose"].kind, MessageKind::pose_stamped);
  expect_samples(read_all(*r));
  expect_samples(read_all(*r, true), true);
}

TEST(Db3, LoneFileReadsWithoutMetadata) {
  ScratchDir dir;
  {
    auto w = create_ros2(dir.path("b"), Ros2Storage::sqlite3);
    write_samples(*w);
  }  // the destructor closes too
  fs::create_directories(dir.path("alone"));
  fs::copy_file(dir.path("b/b_0.db3"), dir.path("alone/x.db3"));
  auto r = open_ros2(dir.path("alone/x.db3"));
  expect_samples(read_all(*r));
}

TEST(Db3, MessagesComeInTimeOrderAndOnlyThoseAsked) {
  ScratchDir dir;
  const std::string file = dir.path("t.db3");
  {
    auto w = ros2::create_sqlite(file);
    w->write("/pose", "geometry_msgs/msg/PoseStamped", 300, cdr::encode_pose_stamped(sample_pose(3.0)));
    w->write("/pose", "geometry_msgs/msg/PoseStamped", 100, cdr::encode_pose_stamped(sample_pose(1.0)));
    w->write("/odom", "nav_msgs/msg/Odometry", 200, cdr::encode_odometry(sample_odometry(2.0)));
    w->close();
  }
  auto r = open_ros2(file);
  std::vector<double> stamps;
  Visitor v;
  v.pose = [&](const std::string&, StampedPose&& p) { stamps.push_back(p.stamp); };
  r->read({"/pose"}, v, false);
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 3.0}));
  stamps.clear();
  r->read({"/pose", "/odom"}, v, false);
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 2.0, 3.0}));
}

TEST(Db3, WrongTypeAndUnknownTopicsAreNamed) {
  ScratchDir dir;
  const std::string file = dir.path("t.db3");
  {
    auto w = ros2::create_sqlite(file);
    w->write("/chatter", "std_msgs/msg/String", 1, {0, 1, 0, 0, 3, 0, 0, 0, 'h', 'i', 0});
    w->close();
  }
  auto r = open_ros2(file);
  ASSERT_EQ(r->topics().size(), 1u);
  EXPECT_EQ(r->topics()[0].kind, MessageKind::other);
  Visitor v;
  v.pose = [](const std::string&, StampedPose&&) {};
  std::string e = error_of([&] { r->read({"/chatter"}, v, false); });
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find("'/chatter'"), std::string::npos) << e;
  EXPECT_NE(e.find("std_msgs/msg/String"), std::string::npos) << e;
  e = error_of([&] { r->read({"/nope"}, v, false); });
  EXPECT_NE(e.find("no topic '/nope'"), std::string::npos) << e;
}

TEST(Db3, MalformedMessageNamesFileTopicAndField) {
  ScratchDir dir;
  const std::string file = dir.path("t.db3");
  std::vector<uint8_t> pose = cdr::encode_pose_stamped(sample_pose(1.0));
  std::fill(pose.end() - 32, pose.end(), 0);  // zero quaternion
  {
    auto w = ros2::create_sqlite(file);
    w->write("/pose", "geometry_msgs/msg/PoseStamped", 42, pose);
    w->close();
  }
  auto r = open_ros2(file);
  Visitor v;
  v.pose = [](const std::string&, StampedPose&&) {};
  const std::string e = error_of([&] { r->read({"/pose"}, v, false); });
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find("'/pose'"), std::string::npos) << e;
  EXPECT_NE(e.find("quaternion"), std::string::npos) << e;
}

TEST(Db3, VisitorErrorsPassThroughUntouched) {
  ScratchDir dir;
  const std::string file = dir.path("t.db3");
  {
    auto w = ros2::create_sqlite(file);
    w->write("/pose", "geometry_msgs/msg/PoseStamped", 42, cdr::encode_pose_stamped(sample_pose(1.0)));
    w->close();
  }
  Visitor v;
  v.pose = [](const std::string&, StampedPose&&) { throw lista::Error("visitor says no"); };
  EXPECT_EQ(error_of([&] { open_ros2(file)->read({"/pose"}, v, false); }), "visitor says no");
}

TEST(Db3, GarbageFileAndBusyFolderAreRefused) {
  ScratchDir dir;
  const std::string file = dir.path("junk.db3");
  std::ofstream(file) << "this is not SQLite at all, not even a little bit, and it goes on for a while";
  const std::string e = error_of([&] { open_ros2(file); });
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(error_of([&] { create_ros2(dir.path(), Ros2Storage::sqlite3); }).find("not an empty folder"), std::string::npos);
  EXPECT_NE(error_of([&] { open_ros2(dir.path("missing")); }).find("no such file"), std::string::npos);
  EXPECT_NE(error_of([&] { open_ros2(dir.path("junk.db3") + "x"); }).find("no such file"), std::string::npos);
}

TEST(Db3, TopicKeepsItsType) {
  ScratchDir dir;
  auto w = create_ros2(dir.path("b"), Ros2Storage::sqlite3);
  w->write_pose_stamped("/p", sample_pose(1.0), 1.0);
  const std::string e = error_of([&] { w->write_odometry("/p", sample_odometry(2.0), 2.0); });
  EXPECT_NE(e.find("'/p'"), std::string::npos) << e;
  w->close();
}

TEST(Db3, SplitBagReadsItsFilesInOrder) {
  ScratchDir dir;
  const std::string bag = dir.path("split");
  fs::create_directories(bag);
  for (int i = 0; i < 2; ++i) {
    auto w = ros2::create_sqlite(bag + "/split_" + std::to_string(i) + ".db3");
    w->write("/pose", "geometry_msgs/msg/PoseStamped", 100 + i, cdr::encode_pose_stamped(sample_pose(1.0 + i)));
    w->close();
  }
  // Foxy wrote the paths with the bag folder's name in front.
  std::ofstream(bag + "/metadata.yaml") << "rosbag2_bagfile_information:\n  version: 4\n  storage_identifier: sqlite3\n"
                                           "  relative_file_paths:\n    - split/split_0.db3\n    - split_1.db3\n";
  auto r = open_ros2(bag);
  ASSERT_EQ(r->topics().size(), 1u);
  EXPECT_EQ(r->topics()[0].messages, 2u);
  std::vector<double> stamps;
  Visitor v;
  v.pose = [&](const std::string&, StampedPose&& p) { stamps.push_back(p.stamp); };
  r->read({"/pose"}, v, false);
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 2.0}));
}
