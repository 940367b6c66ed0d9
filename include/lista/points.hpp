// PointSet: the structure-of-arrays point container that flows between
// stages. Every point keeps its provenance (`scan`, `index`) so that any
// decision can be reported on the original points (data contract, sect. 2).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace lista {

// Bits of PointSet::changed_against.
enum ChangedAgainst : uint8_t {
  changed_against_previous = 1,  // changed against the mission before
  changed_against_next = 2,      // changed against the mission after
  changed_against_either = 3,    // both, or (for a set without the channel) not known
  // Not a neighbour: the point's own mission also saw its voxel free, from
  // another scan (something that moved during the mission: dynamic evidence).
  seen_free_in_own_mission = 4,
};

struct PointSet {
  std::vector<Eigen::Vector3f> xyz;
  std::vector<float> intensity;  // empty, or one per point
  std::vector<uint32_t> label;   // empty, or one per point (ground-truth id)
  // Change points only: empty (not known), or one per point, the
  // ChangedAgainst bits naming the neighbouring missions (previous, next)
  // against which the point was found changed. Matching pairs an object of
  // mission m with one of m+1 only if one of them changed against the
  // other, and calls an unpaired middle-mission object added or removed by
  // them.
  std::vector<uint8_t> changed_against;
  std::vector<uint32_t> scan;    // index of the scan in its mission's poses.txt order
  std::vector<uint32_t> index;   // index of the point in its scan file (non-finite ones counted)

  size_t size() const { return xyz.size(); }
  bool empty() const { return xyz.empty(); }
  bool has_intensity() const { return !intensity.empty(); }
  bool has_label() const { return !label.empty(); }
  bool has_changed_against() const { return !changed_against.empty(); }

  void reserve(size_t n);
  void clear();
  // Appends point i of `other`; the optional channels follow `other`'s
  // (an empty set adopts them, a set that lacks one drops it).
  void push_back_from(const PointSet& other, size_t i);
  // Appends all points of `other`.
  void append(const PointSet& other);
  // The subset at `indices`, in that order.
  PointSet select(const std::vector<uint32_t>& indices) const;
  // Throws lista::Error if the optional channels and provenance do not have
  // one entry per point.
  void check_consistent() const;

  // The neighbour bits (changed_against_either at most) of all points
  // together; changed_against_either when the channel is empty (not known:
  // either neighbour).
  uint8_t changed_against_all() const;
  // How many points carry seen_free_in_own_mission.
  size_t seen_free_count() const;

  Eigen::Vector3f centroid() const;
  // Axis-aligned bounds; (0,0,0) for an empty set.
  void bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const;
};

}  // namespace lista
