// metadata.yaml: the keys a reader needs out of what rosbag2 writes, and
// the refusals (unknown storage, compressed bags) with their file.
#include "bag_fixtures.hpp"
#include "metadata.hpp"

#include <lista_bag/ros2.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace lista::bag;
using namespace lista_test;

namespace {
// As rosbag2 (Humble) writes it: nested keys of the same names under topics
// and files must not be taken for the bag's own.
const char* kHumble = R"(rosbag2_bagfile_information:
  version: 5
  storage_identifier: mcap
  duration:
    nanoseconds: 2000
  starting_time:
    nanoseconds_since_epoch: 1000
  message_count: 3
  topics_with_message_count:
    - topic_metadata:
        name: /points
        type: sensor_msgs/msg/PointCloud2
        serialization_format: cdr
        offered_qos_profiles: "- history: 3\n  depth: 0\n  reliability: 1"
      message_count: 3
  compression_format: ""
  compression_mode: ""
  relative_file_paths:
  - run_0.mcap
  - 'run_1.mcap'
  files:
    - path: run_0.mcap
      storage_identifier: sqlite3
      compression_format: zstd
)";

void write_text(const std::string& file, const std::string& text) { std::ofstream(file) << text; }
}  // namespace

TEST(Metadata, ReadsTheBagsOwnKeys) {
  const ros2::BagMetadata m = ros2::parse_metadata(kHumble, "bag/metadata.yaml");
  EXPECT_EQ(m.storage_identifier, "mcap");
  EXPECT_EQ(m.relative_file_paths, (std::vector<std::string>{"run_0.mcap", "run_1.mcap"}));
  EXPECT_TRUE(m.compression_format.empty());
}

TEST(Metadata, FlowStyleFileList) {
  const ros2::BagMetadata m = ros2::parse_metadata(
      "rosbag2_bagfile_information:\n  storage_identifier: \"sqlite3\"\n  relative_file_paths: [a_0.db3, \"a_1.db3\"]\n", "m.yaml");
  EXPECT_EQ(m.storage_identifier, "sqlite3");
  EXPECT_EQ(m.relative_file_paths, (std::vector<std::string>{"a_0.db3", "a_1.db3"}));
}

TEST(Metadata, UnknownStorageIsNamed) {
  std::string yaml = kHumble;
  yaml.replace(yaml.find("storage_identifier: mcap"), 24, "storage_identifier: rocksdb");
  const std::string e = error_of([&] { ros2::parse_metadata(yaml, "bag/metadata.yaml"); });
  EXPECT_NE(e.find("bag/metadata.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown storage 'rocksdb'"), std::string::npos) << e;
}

TEST(Metadata, CompressedBagSaysHowToDecompress) {
  std::string yaml = kHumble;
  yaml.replace(yaml.find("compression_format: \"\""), 22, "compression_format: zstd");
  yaml.replace(yaml.find("compression_mode: \"\""), 20, "compression_mode: FILE");
  const std::string e = error_of([&] { ros2::parse_metadata(yaml, "bag/metadata.yaml"); });
  EXPECT_NE(e.find("bag/metadata.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("compressed with zstd"), std::string::npos) << e;
  EXPECT_NE(e.find("ros2 bag decompress"), std::string::npos) << e;
}

TEST(Metadata, NotABagsMetadata) {
  EXPECT_NE(error_of([] { ros2::parse_metadata("key: value\n", "x.yaml"); }).find("no storage_identifier"), std::string::npos);
  EXPECT_NE(error_of([] { ros2::parse_metadata("  storage_identifier: mcap\n", "x.yaml"); }).find("relative_file_paths"),
            std::string::npos);
}

TEST(Metadata, WrittenMetadataParsesBack) {
  const std::string text = ros2::format_metadata("sqlite3", "bag_0.db3", {{"/tf", "tf2_msgs/msg/TFMessage", 4}}, 100, 900);
  const ros2::BagMetadata m = ros2::parse_metadata(text, "metadata.yaml");
  EXPECT_EQ(m.storage_identifier, "sqlite3");
  EXPECT_EQ(m.relative_file_paths, std::vector<std::string>{"bag_0.db3"});
  EXPECT_NE(text.find("nanoseconds: 800"), std::string::npos) << text;
  EXPECT_NE(text.find("message_count: 4"), std::string::npos) << text;
}

TEST(Metadata, OpeningABagFolderChecksItsMetadata) {
  ScratchDir dir;
  const std::string bag = dir.path("bag");
  std::filesystem::create_directories(bag);
  EXPECT_NE(error_of([&] { open_ros2(bag); }).find("no metadata.yaml"), std::string::npos);

  std::string yaml = kHumble;
  yaml.replace(yaml.find("storage_identifier: mcap"), 24, "storage_identifier: rocksdb");
  write_text(bag + "/metadata.yaml", yaml);
  std::string e = error_of([&] { open_ros2(bag); });
  EXPECT_NE(e.find(bag + "/metadata.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown storage 'rocksdb'"), std::string::npos) << e;

  write_text(bag + "/metadata.yaml", kHumble);  // lists files that are not there
  e = error_of([&] { open_ros2(bag); });
  EXPECT_NE(e.find("run_0.mcap"), std::string::npos) << e;
  EXPECT_NE(e.find("does not exist"), std::string::npos) << e;
}
