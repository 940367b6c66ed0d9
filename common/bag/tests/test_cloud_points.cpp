#include <gtest/gtest.h>
#include <lista/error.hpp>
#include <lista_bag/cloud_points.hpp>

#include <cstring>

using namespace lista;
using namespace lista::bag;

namespace {

template <class T>
void put(std::vector<uint8_t>& data, size_t at, T v, bool big_endian = false) {
  uint8_t b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  std::memcpy(data.data() + at, b, sizeof(T));
}

// Two rows of two points: x y z as float64, "Intensity" as uint16, "LABEL"
// as uint32, rows padded by 4 bytes.
Cloud organised_cloud(bool big_endian) {
  Cloud c;
  c.height = 2, c.width = 2, c.point_step = 32, c.row_step = 2 * 32 + 4, c.is_bigendian = big_endian;
  c.fields = {{"x", 0, float64, 1}, {"y", 8, float64, 1}, {"z", 16, float64, 1}, {"Intensity", 24, uint16, 1}, {"LABEL", 28, uint32, 1}};
  c.data.assign(size_t(c.row_step) * 2, 0);
  for (int k = 0; k < 4; ++k) {
    const size_t at = size_t(k / 2) * c.row_step + size_t(k % 2) * c.point_step;
    put<double>(c.data, at, 1.0 + k, big_endian);
    put<double>(c.data, at + 8, k == 2 ? std::nan("") : -2.0 * k, big_endian);
    put<double>(c.data, at + 16, 0.5, big_endian);
    put<uint16_t>(c.data, at + 24, uint16_t(100 + k), big_endian);
    put<uint32_t>(c.data, at + 28, uint32_t(7 + k), big_endian);
  }
  return c;
}

}  // namespace

TEST(CloudPoints, ReadsFieldsByNameWhateverTheirCaseTypeAndByteOrder) {
  for (bool big_endian : {false, true}) {
    const io::ScanFile f = cloud_points(organised_cloud(big_endian), 3, "cloud");
    ASSERT_EQ(f.points.size(), 3u) << "the NaN point is skipped";
    EXPECT_EQ(f.points_in_file, 4u);
    EXPECT_EQ(f.skipped_nonfinite, 1u);
    EXPECT_EQ(f.points.index, (std::vector<uint32_t>{0, 1, 3})) << "indexes count the skipped point";
    EXPECT_EQ(f.points.scan, (std::vector<uint32_t>{3, 3, 3}));
    EXPECT_FLOAT_EQ(f.points.xyz[2].x(), 4.0f);
    EXPECT_FLOAT_EQ(f.points.xyz[1].y(), -2.0f);
    EXPECT_EQ(f.points.intensity, (std::vector<float>{100, 101, 103}));
    EXPECT_EQ(f.points.label, (std::vector<uint32_t>{7, 8, 10}));
  }
}

TEST(CloudPoints, ALayoutThatDoesNotHoldItsPointsIsAnError) {
  Cloud c = organised_cloud(false);
  c.data.resize(c.data.size() - 1);
  try {
    cloud_points(c, 0, "bag.bag:/points#4");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bag.bag:/points#4: 135 data bytes do not hold 2 rows"), std::string::npos) << e.what();
  }
  c = organised_cloud(false);
  c.fields[3].offset = 31;
  EXPECT_THROW(cloud_points(c, 0, "c"), Error) << "a field past point_step";
  c = organised_cloud(false);
  c.fields.erase(c.fields.begin() + 2);
  try {
    cloud_points(c, 0, "c");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no 'z' field"), std::string::npos) << e.what();
  }
}
