#include "test_util.hpp"

#include "../src/lzf.hpp"

#include <lista_io/pcd.hpp>

#include <cmath>
#include <cstring>
#include <random>

using namespace lista;
using namespace lista::io;
using namespace lista_io_test;

namespace {

PointSet sample_points(size_t n, bool labels = true) {
  PointSet p;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-50.f, 50.f);
  for (size_t i = 0; i < n; ++i) {
    p.xyz.emplace_back(u(rng), u(rng), u(rng));
    p.intensity.push_back(float(i % 17) * 0.25f);
    if (labels) p.label.push_back(uint32_t(i % 5));
    p.scan.push_back(0);
    p.index.push_back(uint32_t(i));
  }
  return p;
}

void expect_same(const PointSet& a, const PointSet& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.xyz[i], b.xyz[i]) << i;
    ASSERT_EQ(a.intensity[i], b.intensity[i]) << i;
    if (a.has_label()) {
      ASSERT_EQ(a.label[i], b.label[i]) << i;
    }
    ASSERT_EQ(b.index[i], i);
  }
}

}  // namespace

TEST(Lzf, RoundTripsRepetitiveAndRandomData) {
  std::vector<uint8_t> data(100000);
  std::mt19937 rng(1);
  for (size_t i = 0; i < data.size(); ++i) data[i] = i < 50000 ? uint8_t(i % 13) : uint8_t(rng());
  std::vector<uint8_t> packed;
  lzf::compress(data.data(), data.size(), packed);
  EXPECT_LT(packed.size(), data.size());  // the repetitive half compresses
  std::vector<uint8_t> back(data.size());
  ASSERT_TRUE(lzf::decompress(packed.data(), packed.size(), back.data(), back.size()));
  EXPECT_EQ(back, data);
  // A corrupt stream is refused, not trusted.
  packed.resize(packed.size() / 2);
  EXPECT_FALSE(lzf::decompress(packed.data(), packed.size(), back.data(), back.size()));
}

TEST(Lzf, DecodesHandMadeStream) {
  // literal "ab" (ctrl 1), then back reference distance 2 length 4 -> "ababab".
  const uint8_t stream[] = {1, 'a', 'b', uint8_t((2 << 5) | 0), 1};
  uint8_t out[6];
  ASSERT_TRUE(lzf::decompress(stream, sizeof stream, out, 6));
  EXPECT_EQ(std::string(reinterpret_cast<char*>(out), 6), "ababab");
}

class PcdEncodings : public ::testing::TestWithParam<PcdEncoding> {};

TEST_P(PcdEncodings, ScanRoundTrip) {
  const auto dir = temp_dir("pcd");
  const PointSet pts = sample_points(3000);
  const std::string path = (dir / "scan.pcd").string();
  write_scan_pcd(path, pts, GetParam());
  const ScanFile back = read_scan(path, 42);
  EXPECT_EQ(back.points_in_file, 3000u);
  EXPECT_EQ(back.skipped_nonfinite, 0u);
  EXPECT_FALSE(back.viewpoint.has_value());
  expect_same(pts, back.points);
  EXPECT_EQ(back.points.scan.front(), 42u);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp." + std::to_string(::getpid())));
}

TEST_P(PcdEncodings, TableKeepsTypedColumnsAndViewpoint) {
  const auto dir = temp_dir("pcd");
  std::vector<float> x = {1.5f, -2.f}, y = {0.f, 3.f}, z = {7.f, 8.f};
  std::vector<uint32_t> scan = {4000000000u, 1u};
  std::vector<int32_t> obj = {-1, 12};
  Eigen::Isometry3d vp = Eigen::Isometry3d::Identity();
  vp.translate(Eigen::Vector3d(1, 2, 3));
  vp.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const std::string path = (dir / "t.pcd").string();
  write_pcd(path, 2, {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()},
                      {"scan", 'U', scan.data()}, {"object", 'I', obj.data()}},
            GetParam(), vp);
  const PcdTable t = read_pcd_table(path);
  ASSERT_EQ(t.size, 2u);
  ASSERT_EQ(t.column("object"), 4);
  EXPECT_EQ(t.column("nope"), -1);
  EXPECT_EQ(t.types[3], 'U');
  EXPECT_EQ(t.types[4], 'I');
  EXPECT_EQ(t.values[3][0], 4000000000.0);
  EXPECT_EQ(t.values[4][0], -1.0);
  EXPECT_EQ(t.values[4][1], 12.0);
  EXPECT_EQ(t.values[0][0], 1.5);
  const ScanFile s = read_scan(path);
  ASSERT_TRUE(s.viewpoint.has_value());
  EXPECT_TRUE(s.viewpoint->isApprox(vp, 1e-12));
}

INSTANTIATE_TEST_SUITE_P(AllEncodings, PcdEncodings,
                         ::testing::Values(PcdEncoding::ascii, PcdEncoding::binary, PcdEncoding::binary_compressed));

TEST(PcdRead, AsciiWithRgbPaddingCountsAndNonFinite) {
  const auto dir = temp_dir("pcd");
  // rgb packed float, a padding field, a 3-count normal, double x, uchar label.
  write_text(dir / "a.pcd",
             "# comment\nVERSION .7\nFIELDS x y z rgb _ normal intensity label\n"
             "SIZE 8 4 4 4 1 4 2 1\nTYPE F F F F U F U U\nCOUNT 1 1 1 1 1 3 1 1\n"
             "WIDTH 4\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
             "1 2 3 4.2e-38 0 0 0 1 100 7\n"
             "nan nan nan 0 0 0 0 1 5 0\n"
             "\n"
             "4 5 inf 0 0 0 0 1 5 0\n"
             "-1 -2 -3 0 0 0 0 1 65535 255\n");
  const ScanFile s = read_scan((dir / "a.pcd").string(), 3);
  EXPECT_EQ(s.points_in_file, 4u);
  EXPECT_EQ(s.skipped_nonfinite, 2u);
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_EQ(s.points.index[0], 0u);
  EXPECT_EQ(s.points.index[1], 3u);  // index counts the non-finite rows
  EXPECT_EQ(s.points.xyz[1], Eigen::Vector3f(-1, -2, -3));
  EXPECT_EQ(s.points.intensity[0], 100.f);
  EXPECT_EQ(s.points.label[1], 255u);
  EXPECT_FALSE(s.viewpoint.has_value());
}

// Exporters name fields their own way: PDAL and CloudCompare capitalise
// ("X", "Intensity"); a LiDAR driver may give only its reflectivity. Field
// names are matched case-insensitively, and intensity is taken from
// intensity, else scalar_intensity, else reflectivity.
TEST(PcdRead, FieldNamesOfOtherExporters) {
  const auto dir = temp_dir("pcd");
  const std::string rows = "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 40 7\n4 5 6 50 8\n";
  write_text(dir / "caps.pcd", "FIELDS X Y Z Intensity Reflectivity\nSIZE 4 4 4 4 4\nTYPE F F F F F\n" + rows);
  write_text(dir / "refl.pcd", "FIELDS x y z ring reflectivity\nSIZE 4 4 4 4 4\nTYPE F F F F F\n" + rows);
  write_text(dir / "none.pcd", "FIELDS x y z ring range\nSIZE 4 4 4 4 4\nTYPE F F F F F\n" + rows);
  const ScanFile caps = read_scan((dir / "caps.pcd").string(), 0);
  ASSERT_EQ(caps.points.size(), 2u);
  EXPECT_EQ(caps.points.xyz[1], Eigen::Vector3f(4, 5, 6));
  ASSERT_TRUE(caps.points.has_intensity());
  EXPECT_EQ(caps.points.intensity[0], 40.f);  // Intensity, not Reflectivity
  const ScanFile refl = read_scan((dir / "refl.pcd").string(), 0);
  ASSERT_TRUE(refl.points.has_intensity());
  EXPECT_EQ(refl.points.intensity[1], 8.f);
  EXPECT_FALSE(read_scan((dir / "none.pcd").string(), 0).points.has_intensity());
}

TEST(PcdRead, BinaryWithMixedSizes) {
  const auto dir = temp_dir("pcd");
  std::string head = "FIELDS x y z _ label\nSIZE 4 4 8 2 2\nTYPE F F F U U\nCOUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n";
  std::string body;
  auto put = [&](const void* p, size_t n) { body.append(static_cast<const char*>(p), n); };
  for (int i = 0; i < 2; ++i) {
    float x = 1.f + i, y = 2.f;
    double z = 3.5;
    uint16_t pad = 0xBEEF, label = uint16_t(9 + i);
    put(&x, 4); put(&y, 4); put(&z, 8); put(&pad, 2); put(&label, 2);
  }
  write_text(dir / "b.pcd", head + body);
  const ScanFile s = read_scan((dir / "b.pcd").string());
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_EQ(s.points.xyz[1], Eigen::Vector3f(2, 2, 3.5));
  EXPECT_EQ(s.points.label[1], 10u);
  EXPECT_FALSE(s.points.has_intensity());
}

TEST(PcdRead, MalformedFilesNameFileAndLine) {
  const auto dir = temp_dir("pcd");
  const std::string head = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 2\nDATA ascii\n";
  write_text(dir / "short.pcd", head + "1 2 3\n4 5\n");
  expect_error([&] { read_scan((dir / "short.pcd").string()); }, "short.pcd:8: expected 3 values, got 2");
  write_text(dir / "word.pcd", head + "1 2 3\n4 x 6\n");
  expect_error([&] { read_scan((dir / "word.pcd").string()); }, "word.pcd:8: 'x' is not a number");
  write_text(dir / "rows.pcd", head + "1 2 3\n");
  expect_error([&] { read_scan((dir / "rows.pcd").string()); }, "1 data rows, POINTS says 2");
  write_text(dir / "type.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F Q F\nWIDTH 1\nDATA ascii\n");
  expect_error([&] { read_scan((dir / "type.pcd").string()); }, "type.pcd:3: TYPE 'Q'");
  write_text(dir / "noxyz.pcd", "FIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nWIDTH 0\nDATA ascii\n");
  expect_error([&] { read_scan((dir / "noxyz.pcd").string()); }, "lacks one of the fields x, y, z");
  write_text(dir / "trunc.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA binary\n12345678");
  expect_error([&] { read_scan((dir / "trunc.pcd").string()); }, "truncated binary data");
  write_text(dir / "extra.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA binary\n123456789012more");
  expect_error([&] { read_scan((dir / "extra.pcd").string()); }, "4 bytes of binary data after the 1 points");
  static const char lzf_bad[] = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA binary_compressed\n"
                                "\x05\0\0\0\x0c\0\0\0\x40\x01\x02\x03\x04";
  write_text(dir / "lzf.pcd", std::string(lzf_bad, sizeof lzf_bad - 1));
  expect_error([&] { read_scan((dir / "lzf.pcd").string()); }, "corrupt binary_compressed");
  expect_error([&] { read_scan((dir / "missing.pcd").string()); }, "missing.pcd: cannot read");
  expect_error([&] { read_scan((dir / "x.las").string()); }, "unknown scan file type");
  write_text(dir / "junk.pcd", std::string("\x8f\x01\xfe\x7f random bytes\n", 18));
  expect_error([&] { read_scan((dir / "junk.pcd").string()); }, "junk.pcd:1: not a PCD file (binary data where");
  write_text(dir / "key.pcd", "FIELDS x y z\nCOLOUR red\n");
  expect_error([&] { read_scan((dir / "key.pcd").string()); }, "key.pcd:2: unknown PCD header keyword 'COLOUR'");
}

// Headers that lie about their size: refused before memory is reserved for
// them (a 200-byte file must not allocate gigabytes), overflow included.
TEST(PcdRead, LyingHeadersAreRefusedBeforeAllocating) {
  const auto dir = temp_dir("pcd-lie");
  write_text(dir / "bomb.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 50000000\nDATA ascii\n1 2 3\n");
  expect_error([&] { read_scan((dir / "bomb.pcd").string()); }, "bomb.pcd: 6 bytes of ascii data cannot hold POINTS 50000000");
  write_text(dir / "wrap.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4294967296\nHEIGHT 4294967296\n"
                               "POINTS 0\nDATA ascii\n1 2 3\n");
  expect_error([&] { read_scan((dir / "wrap.pcd").string()); }, "wrap.pcd:7: WIDTH 4294967296 x HEIGHT 4294967296");
  write_text(dir / "wide.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 100000000\nWIDTH 1\nDATA binary\n");
  expect_error([&] { read_scan((dir / "wide.pcd").string()); }, "more than 1 MiB per point");
  write_text(dir / "nanvp.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nVIEWPOINT nan 0 0 1 0 0 0\n"
                                "DATA ascii\n1 2 3\n");
  expect_error([&] { read_scan((dir / "nanvp.pcd").string()); }, "nanvp.pcd:5: VIEWPOINT: 'nan' is not a finite number");
}

// Labels are uint32 object ids; another tool's -1 or 1.5 drops the channel
// (lista-eval then says the scan has no usable labels) instead of wrapping.
TEST(PcdRead, LabelsThatAreNoObjectIdsAreDropped) {
  const auto dir = temp_dir("pcd-label");
  const std::string head = "FIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F I\nWIDTH 2\nDATA ascii\n";
  write_text(dir / "good.pcd", head + "1 2 3 7\n4 5 6 0\n");
  const ScanFile good = read_scan((dir / "good.pcd").string());
  EXPECT_FALSE(good.bad_labels);
  EXPECT_EQ(good.points.label, (std::vector<uint32_t>{7, 0}));
  write_text(dir / "bad.pcd", head + "1 2 3 7\n4 5 6 -1\n");
  const ScanFile bad = read_scan((dir / "bad.pcd").string());
  EXPECT_TRUE(bad.bad_labels);
  EXPECT_FALSE(bad.points.has_label());
  EXPECT_EQ(bad.points.size(), 2u);
}

TEST(PcdWrite, RefusesBadColumnsAndLeavesNoFile) {
  const auto dir = temp_dir("pcd");
  std::vector<float> x = {1.f};
  expect_error([&] { write_pcd((dir / "bad.pcd").string(), 1, {{"x", 'D', x.data()}}); }, "expected F, U or I");
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.pcd"));
  expect_error([&] { write_pcd((dir / "nodir" / "a.pcd").string(), 1, {{"x", 'F', x.data()}}); }, "cannot write");
}
