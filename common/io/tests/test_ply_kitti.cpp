#include "test_util.hpp"

#include <lista_io/pcd.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace lista::io;
using namespace lista_io_test;

namespace {
template <class T>
void put(std::string& s, T v, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}
}  // namespace

TEST(Ply, AsciiSkipsTheElementsAroundTheVertices) {
  const auto dir = temp_dir("ply");
  write_text(dir / "a.ply",
             "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 3\nproperty float x\n"
             "property float y\nproperty float z\nproperty uchar intensity\nproperty uint label\n"
             "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "1 2 3 10 4\nnan 0 0 0 0\n-1 -2 -3.5 255 0\n3 0 1 2\n");
  const ScanFile s = read_scan((dir / "a.ply").string(), 1);
  EXPECT_EQ(s.points_in_file, 3u);
  EXPECT_EQ(s.skipped_nonfinite, 1u);
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_EQ(s.points.xyz[1], Eigen::Vector3f(-1, -2, -3.5f));
  EXPECT_EQ(s.points.index[1], 2u);
  EXPECT_EQ(s.points.intensity[1], 255.f);
  EXPECT_EQ(s.points.label[0], 4u);

  // An element before the vertices: its lines are skipped (a blank one
  // among them too), and the vertices keep their own indices.
  write_text(dir / "b.ply",
             "ply\nformat ascii 1.0\nelement camera 2\nproperty float f\nelement vertex 2\n"
             "property float x\nproperty float y\nproperty float z\nend_header\n500\n\n600\n1 2 3\n4 5 6\n");
  const ScanFile before = read_scan((dir / "b.ply").string(), 0);
  ASSERT_EQ(before.points.size(), 2u);
  EXPECT_EQ(before.points.xyz[0], Eigen::Vector3f(1, 2, 3));
  EXPECT_EQ(before.points.index[1], 1u);
}

// CloudCompare's export: capitalised coordinates, intensity as a scalar
// field, which wins over a reflectivity property (PcdRead's rule).
TEST(Ply, FieldNamesOfOtherExporters) {
  const auto dir = temp_dir("ply");
  write_text(dir / "cc.ply",
             "ply\nformat ascii 1.0\nelement vertex 2\nproperty float reflectivity\nproperty double X\n"
             "property double Y\nproperty double Z\nproperty float scalar_Intensity\nend_header\n"
             "9 1 2 3 40\n9 4 5 6 50\n");
  const ScanFile s = read_scan((dir / "cc.ply").string(), 0);
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_EQ(s.points.xyz[1], Eigen::Vector3f(4, 5, 6));
  ASSERT_TRUE(s.points.has_intensity());
  EXPECT_EQ(s.points.intensity[0], 40.f);
}

class PlyBinary : public ::testing::TestWithParam<bool> {};

TEST_P(PlyBinary, BothEndiannessesWithSkippedElement) {
  const bool big = GetParam();
  const auto dir = temp_dir("ply");
  std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement camera 1\nproperty double f\nelement vertex 2\nproperty double x\n"
                  "property float y\nproperty float z\nproperty float intensity\nproperty ushort label\nend_header\n";
  put(s, 99.0, big);  // the camera element, skipped
  for (int i = 0; i < 2; ++i) {
    put(s, 1.25 + i, big);
    put(s, -2.f, big);
    put(s, 3.f * i, big);
    put(s, 0.5f, big);
    put(s, uint16_t(300 + i), big);
  }
  write_text(dir / "b.ply", s);
  const ScanFile f = read_scan((dir / "b.ply").string());
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_EQ(f.points.xyz[1], Eigen::Vector3f(2.25f, -2.f, 3.f));
  EXPECT_EQ(f.points.intensity[0], 0.5f);
  EXPECT_EQ(f.points.label[1], 301u);
}

INSTANTIATE_TEST_SUITE_P(Endianness, PlyBinary, ::testing::Values(false, true));

TEST(Ply, MalformedFiles) {
  const auto dir = temp_dir("ply");
  write_text(dir / "a.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                            "property float z\nend_header\n1 2 3\n4 5\n");
  expect_error([&] { read_scan((dir / "a.ply").string()); }, "a.ply:9: expected 3 values, got 2");
  write_text(dir / "b.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n");
  expect_error([&] { read_scan((dir / "b.ply").string()); }, "lacks one of x, y, z");
  write_text(dir / "c.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                            "property float y\nproperty float z\nend_header\n1234");
  expect_error([&] { read_scan((dir / "c.ply").string()); }, "truncated binary PLY");
  write_text(dir / "d.ply", "solid x\n");
  expect_error([&] { read_scan((dir / "d.ply").string()); }, "not a PLY file");
  write_text(dir / "e.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n");
  expect_error([&] { read_scan((dir / "e.ply").string()); }, "e.ply:4: unknown property type 'quad'");
  // Counts whose byte sizes would wrap: a corrupt header, said so.
  write_text(dir / "f.ply", "ply\nformat binary_little_endian 1.0\nelement face 4611686018427387904\n"
                            "property float a\nelement vertex 1\nproperty float x\nproperty float y\n"
                            "property float z\nend_header\n123456789012");
  expect_error([&] { read_scan((dir / "f.ply").string()); }, "f.ply:3: element 'face' has 4611686018427387904 items");
  // A huge vertex count reserves nothing before the data is found missing.
  write_text(dir / "g.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                            "property float y\nproperty float z\nend_header\n1234");
  expect_error([&] { read_scan((dir / "g.ply").string()); }, "truncated binary PLY");
  // More rows than the count (vertex the last element) is a wrong header, as in PCD.
  write_text(dir / "h.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                            "property float z\nend_header\n1 2 3\n4 5 6\n\n");
  expect_error([&] { read_scan((dir / "h.ply").string()); }, "h.ply:9: more data rows than 'element vertex 1'");
  write_text(dir / "i.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                            "property float y\nproperty float z\nend_header\n123456789012EXTRA");
  expect_error([&] { read_scan((dir / "i.ply").string()); }, "5 bytes of binary data after the 1 vertices");
  write_text(dir / "j.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                            "property float y\nproperty float z\nend_header\n123456789012\n");
  EXPECT_EQ(read_scan((dir / "j.ply").string()).points.size(), 1u) << "a closing newline is no row";
}

TEST(KittiBin, ReadsFloatQuadruplesAndCountsNonFinite) {
  const auto dir = temp_dir("kitti");
  std::string s;
  const float pts[3][4] = {{1, 2, 3, 0.5f}, {NAN, 0, 0, 0}, {-4, 5, -6, 0.25f}};
  for (auto& p : pts)
    for (float v : p) put(s, v, false);
  write_text(dir / "000000.bin", s);
  const ScanFile f = read_scan((dir / "000000.bin").string(), 5);
  EXPECT_EQ(f.points_in_file, 3u);
  EXPECT_EQ(f.skipped_nonfinite, 1u);
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_EQ(f.points.xyz[1], Eigen::Vector3f(-4, 5, -6));
  EXPECT_EQ(f.points.intensity[1], 0.25f);
  EXPECT_EQ(f.points.index[1], 2u);
  EXPECT_EQ(f.points.scan[0], 5u);
  EXPECT_FALSE(f.points.has_label());
  write_text(dir / "bad.bin", s + "xyz");
  expect_error([&] { read_scan((dir / "bad.bin").string()); }, "not a multiple of 16");
}
