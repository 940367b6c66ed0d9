// .mcap bags: every chunk compression with and without a summary section,
// the bag folder, and damaged files answered with errors naming the file.
#include "bag_fixtures.hpp"
#include "cdr.hpp"
#include "mcap_format.hpp"

#include <lista_bag/ros2.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;
using namespace lista::bag;
using namespace lista_test;

namespace {

std::string write_mcap(const ScratchDir& dir, ros2::McapOptions options, const std::string& name = "m.mcap") {
  const std::string file = dir.path(name);
  auto w = ros2::create_mcap(file, options);
  write_samples(*w);
  w->close();
  return file;
}

ros2::McapOptions options(ros2::McapCompression c, bool summary, size_t chunk_bytes = 200) {
  ros2::McapOptions o;
  o.compression = c;
  o.summary = summary;
  o.chunk_bytes = chunk_bytes;  // small: several chunks, a topic's Channel in one and its messages in later ones
  return o;
}

// Where `what` starts in `bytes`.
size_t find(const std::vector<uint8_t>& bytes, const std::string& what) {
  const auto it = std::search(bytes.begin(), bytes.end(), what.begin(), what.end());
  return it == bytes.end() ? std::string::npos : static_cast<size_t>(it - bytes.begin());
}

}  // namespace

class McapRoundTrip : public testing::TestWithParam<std::tuple<ros2::McapCompression, bool>> {};

TEST_P(McapRoundTrip, EveryMessageComesBack) {
  ScratchDir dir;
  const auto [compression, summary] = GetParam();
  const std::string file = write_mcap(dir, options(compression, summary));
  const std::vector<uint8_t> bytes = read_bytes(file);
  // The chunks say their compression (a uint32-prefixed string).
  const bool zstd = find(bytes, std::string("\x04\0\0\0zstd", 8)) != std::string::npos;
  const bool lz4 = find(bytes, std::string("\x03\0\0\0lz4", 7)) != std::string::npos;
  EXPECT_EQ(zstd, compression == ros2::McapCompression::zstd);
  EXPECT_EQ(lz4, compression == ros2::McapCompression::lz4);
  auto r = open_ros2(file);
  std::map<std::string, uint64_t> counts;
  for (const TopicInfo& t : r->topics()) counts[t.name] = t.messages;
  EXPECT_EQ(counts, (std::map<std::string, uint64_t>{{"/odom", 1}, {"/points", 2}, {"/pose", 1}, {"/tf", 2}, {"/tf_static", 1}}));
  expect_samples(read_all(*r));
  expect_samples(read_all(*r, true), true);
}

INSTANTIATE_TEST_SUITE_P(Chunks, McapRoundTrip,
                         testing::Combine(testing::Values(ros2::McapCompression::zstd, ros2::McapCompression::lz4,
                                                          ros2::McapCompression::none),
                                          testing::Bool()));

TEST(Mcap, BagFolderRoundTrip) {
  ScratchDir dir;
  const std::string bag = dir.path("run");
  {
    auto w = create_ros2(bag, Ros2Storage::mcap);
    write_samples(*w);
    w->close();
  }
  ASSERT_TRUE(std::filesystem::exists(bag + "/metadata.yaml"));
  ASSERT_TRUE(fs::exists(bag + "/run_0.mcap"));
  auto r = open_ros2(bag + "/metadata.yaml");  // the metadata file stands for its folder
  expect_samples(read_all(*r));
  expect_samples(read_all(*open_ros2(bag + "/run_0.mcap")));
}

TEST(Mcap, TruncatedFileIsAnError) {
  ScratchDir dir;
  const std::string file = write_mcap(dir, options(ros2::McapCompression::zstd, false));
  const std::vector<uint8_t> bytes = read_bytes(file);
  const std::string cut = dir.path("cut.mcap");
  // DataEnd (13 bytes), Footer (29) and the closing magic (8) end the file;
  // any cut before DataEnd loses data.
  for (size_t n = 0; n <= bytes.size() - 50; ++n) {
    write_bytes(cut, std::vector<uint8_t>(bytes.begin(), bytes.begin() + n));
    const std::string e = error_of([&] { read_all(*open_ros2(cut)); });
    ASSERT_NE(e.find(cut), std::string::npos) << n << ": " << e;
  }
  write_bytes(cut, std::vector<uint8_t>(bytes.begin(), bytes.begin() + bytes.size() / 2));
  EXPECT_NE(error_of([&] { read_all(*open_ros2(cut)); }).find("truncated"), std::string::npos);
}

TEST(Mcap, UnknownCompressionIsNamed) {
  ScratchDir dir;
  const std::string file = write_mcap(dir, options(ros2::McapCompression::lz4, false));
  std::vector<uint8_t> bytes = read_bytes(file);
  const size_t at = find(bytes, std::string("\x03\0\0\0lz4", 7));
  ASSERT_NE(at, std::string::npos);
  std::copy_n("br8", 3, bytes.begin() + at + 4);
  write_bytes(file, bytes);
  const std::string e = error_of([&] { read_all(*open_ros2(file)); });
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find("unknown chunk compression 'br8'"), std::string::npos) << e;
}

TEST(Mcap, ForgedUncompressedSizeIsRefused) {
  ScratchDir dir;
  const std::string file = write_mcap(dir, options(ros2::McapCompression::zstd, false, 1 << 20));
  std::vector<uint8_t> bytes = read_bytes(file);
  const size_t at = find(bytes, std::string("\x04\0\0\0zstd", 8));
  ASSERT_NE(at, std::string::npos);
  // uncompressed_size and its crc sit just before the compression string.
  for (uint64_t forged : {uint64_t(1) << 40, uint64_t(50) << 20}) {
    for (int i = 0; i < 8; ++i) bytes[at - 12 + i] = static_cast<uint8_t>(forged >> (8 * i));
    write_bytes(file, bytes);
    const std::string e = error_of([&] { read_all(*open_ros2(file)); });
    EXPECT_NE(e.find(file), std::string::npos) << e;
    EXPECT_NE(e.find("uncompressed_size"), std::string::npos) << e;
  }
}

TEST(Mcap, OnlyCdrMessagesAreRead) {
  ScratchDir dir;
  ros2::McapOptions o;
  o.message_encoding = "json";
  const std::string file = write_mcap(dir, o);
  auto r = open_ros2(file);
  Visitor v;
  v.pose = [](const std::string&, StampedPose&&) {};
  const std::string e = error_of([&] { r->read({"/odom"}, v, false); });
  EXPECT_NE(e.find("'/odom'"), std::string::npos) << e;
  EXPECT_NE(e.find("'json'"), std::string::npos) << e;
}

TEST(Mcap, NotAnMcapFile) {
  ScratchDir dir;
  const std::string file = dir.path("x.mcap");
  write_bytes(file, {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'});
  const std::string e = error_of([&] { open_ros2(file); });
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find("not an MCAP file"), std::string::npos) << e;
}

// Seeds for fuzz/corpus/: ./test_lista_ros2bag --gtest_also_run_disabled_tests
// --gtest_filter='*WriteFuzzSeeds' with LISTA_FUZZ_SEEDS=<source>/fuzz/corpus.
TEST(Mcap, DISABLED_WriteFuzzSeeds) {
  const char* out = std::getenv("LISTA_FUZZ_SEEDS");
  ASSERT_TRUE(out);
  const std::string corpus = out;
  fs::create_directories(corpus + "/mcap");
  fs::create_directories(corpus + "/cdr");
  ScratchDir dir;
  for (const auto& [name, o] : {std::pair{"zstd.mcap", options(ros2::McapCompression::zstd, true, 400)},
                                std::pair{"lz4.mcap", options(ros2::McapCompression::lz4, false, 400)},
                                std::pair{"plain.mcap", options(ros2::McapCompression::none, true, 400)}})
    fs::copy_file(write_mcap(dir, o, name), corpus + "/mcap/" + name, fs::copy_options::overwrite_existing);
  Cloud small = sample_cloud(1.0);
  write_bytes(corpus + "/cdr/cloud.cdr", cdr::encode_cloud(small));
  write_bytes(corpus + "/cdr/cloud_be.cdr", cdr::encode_cloud(small, true));
  write_bytes(corpus + "/cdr/tf.cdr", cdr::encode_tf(sample_tf(2.0)));
  write_bytes(corpus + "/cdr/odometry.cdr", cdr::encode_odometry(sample_odometry(3.0)));
  write_bytes(corpus + "/cdr/pose.cdr", cdr::encode_pose_stamped(sample_pose(4.0), true));
}
