// PointSet: the structure-of-arrays point container that flows between
// stages. Every point keeps its provenance (`scan`, `index`) so that any
// decision can be reported on the original points (data contract, sect. 2).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace lista {

struct PointSet {
  std::vector<Eigen::Vector3f> xyz;
  std::vector<float> intensity;  // empty, or one per point
  std::vector<uint32_t> label;   // empty, or one per point (ground-truth id)
  std::vector<uint32_t> scan;    // index of the scan in its mission's poses.txt order
  std::vector<uint32_t> index;   // index of the point in its scan file (non-finite ones counted)

  size_t size() const { return xyz.size(); }
  bool empty() const { return xyz.empty(); }
  bool has_intensity() const { return !intensity.empty(); }
  bool has_label() const { return !label.empty(); }

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

  Eigen::Vector3f centroid() const;
  // Axis-aligned bounds; (0,0,0) for an empty set.
  void bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const;
};

}  // namespace lista
