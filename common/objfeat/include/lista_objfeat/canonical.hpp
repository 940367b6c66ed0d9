// Turns one object's points (any count, partial view, any density, any yaw)
// into a fixed-size, yaw-canonical point set: the input of the learned
// descriptor, shared by describe.learned, lista-train and the benchmark so the
// three always see exactly the same preprocessing.
//
// Steps (all O(n) or O(n log n), deterministic):
//  1. centre on the centroid;
//  2. yaw: rotate about z so +x is the longer side of the footprint's
//     minimum-perimeter bounding rectangle (or, in the first model's frame, the
//     major principal axis of the horizontal spread), its sign fixed by the
//     third moment (skew) along it; objects stand on floors, so z stays up
//     and only yaw is removed;
//  3. voxel-grid in that frame (cell = extent / grid) so dense near-sensor
//     patches do not dominate, one centroid per occupied cell;
//  4. pick exactly `points` cells with a seeded shuffle (repeat cells when
//     there are fewer), in cell-key order so the result does not depend on
//     the input order's relation to the frame (each picked cell gives the
//     per-point channels below);
//  5. shape globals (kShapeGlobals): extents, the centroid's height above
//     the lowest point (or the floor), the footprint's fitted circle and
//     robust spreads, the sizes the resampling would blur, and the lowest
//     point's height above the floor.
// Heights are measured from the floor the object stands on when the caller
// knows it and the configuration asks for it (CanonicalConfig::floor), else
// from the object's lowest point. Why: a sensor near an object often misses
// its bottom (a 16-beam LiDAR's lowest beam is 15 degrees down, so from a
// 1.8 m mount it cuts objects under 1.3 m at 2 m range), and the lowest
// point then lies on the object's flank, not on the floor.
// Rotating the input about z changes nothing but float rounding.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace lista::objfeat {

constexpr float kUnknownFloor = std::numeric_limits<float>::quiet_NaN();

// How yaw is fixed. bounding_rectangle lines up with the faces of box-like
// objects even in partial views; principal_axis is the first shipped model's
// frame (weights files record which one they were trained with).
enum class YawFrame : int { principal_axis = 0, bounding_rectangle = 1 };

struct CanonicalConfig {
  int points = 256;        // fixed output size
  int grid = 24;           // voxel cells along the largest extent
  // Selection seed. describe.learned and lista-train evaluation use this
  // default so a descriptor is a pure function of the points.
  uint64_t seed = 0x5eed;
  YawFrame frame = YawFrame::bounding_rectangle;
  // Measure heights (channel 5, globals 3 and 9) from the floor when one is
  // given; false: always from the lowest point (models without the floor).
  bool floor = false;
};

// Per-point input channels: x, y, z (canonical frame, metres), horizontal
// radius, distance to the centroid, and height above the object's lowest
// point (above the floor when it is known and used). The last one does not move when a partial view shifts the centroid
// (objects stand on floors, and the floor contact is seen from most sides).
// A network reads the first `NetConfig::in` of them: 5-channel weights (the
// models before the height channel) see exactly what they were trained on.
constexpr int kCanonicalChannels = 6;
constexpr int kFirstModelChannels = 5;
// Shape globals (metres), all computed; a network reads the first
// `NetConfig::globals` of them:
//  0-3: extent along canonical x, y, z (all points) and the centroid's height
//       above the lowest point, or above the floor when it is known and used
//       (the 4 globals of earlier models);
//  4-5: radius of the circle fitted to the footprint (algebraic least
//       squares on the voxel cells' x/y; capped at twice the horizontal
//       extent, so a flat face reads as "very large") and the fit's RMS
//       residual: the curvature of round objects, which the resampled cells
//       blur and a partial view's extents under-state;
//  6-8: 2nd-98th percentile spread of the voxel cells along canonical x, y,
//       z: sizes that a few noisy or stray points do not stretch, and that
//       do not grow with the point count as max - min does;
//  9:   the lowest point's height above the floor (0 when the floor is not
//       known or not used): how much of the object's bottom the view missed.
constexpr int kExtentGlobals = 4;
constexpr int kNoFloorGlobals = 9;
constexpr int kShapeGlobals = 10;
// The counts a network may read: none (the first model), the four extent
// globals (models before 2026-11-25 evening), the nine before the floor
// (models before 2026-11-26) or all.
constexpr bool valid_global_count(int n) {
  return n == 0 || n == kExtentGlobals || n == kNoFloorGlobals || n == kShapeGlobals;
}

struct CanonicalCloud {
  // points x kCanonicalChannels, row-major.
  std::vector<float> features;
  std::array<float, kShapeGlobals> globals{};
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();  // world -> canonical (about z)
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  int points = 0;
};

// `floor_z`: height of the floor under the object in the frame of `xyz`
// (NaN: unknown; ignored unless config.floor). Throws lista::Error for an
// empty input or non-positive sizes.
CanonicalCloud make_canonical(const std::vector<Eigen::Vector3f>& xyz, const CanonicalConfig& config,
                              float floor_z = kUnknownFloor);
// `samples` clouds of one object that differ only in the cell selection
// (step 4, seeds config.seed + k); steps 1-3 and 5 are done once. Element k
// equals make_canonical with seed config.seed + k. Throws as make_canonical,
// and for samples < 1.
std::vector<CanonicalCloud> make_canonical_samples(const std::vector<Eigen::Vector3f>& xyz,
                                                  const CanonicalConfig& config, int samples,
                                                  float floor_z = kUnknownFloor);

}  // namespace lista::objfeat
