#include <lista/error.hpp>
#include <lista/points.hpp>

#include <algorithm>

namespace lista {

void PointSet::reserve(size_t n) {
  xyz.reserve(n);
  scan.reserve(n);
  index.reserve(n);
  if (has_intensity()) intensity.reserve(n);
  if (has_label()) label.reserve(n);
  if (has_changed_against()) changed_against.reserve(n);
}

void PointSet::clear() {
  xyz.clear();
  intensity.clear();
  label.clear();
  changed_against.clear();
  scan.clear();
  index.clear();
}

void PointSet::push_back_from(const PointSet& other, size_t i) {
  const bool first = empty();
  xyz.push_back(other.xyz[i]);
  if (other.has_intensity() && (first || has_intensity())) intensity.push_back(other.intensity[i]);
  else intensity.clear();
  if (other.has_label() && (first || has_label())) label.push_back(other.label[i]);
  else label.clear();
  if (other.has_changed_against() && (first || has_changed_against()))
    changed_against.push_back(other.changed_against[i]);
  else
    changed_against.clear();
  scan.push_back(other.scan.empty() ? 0u : other.scan[i]);
  index.push_back(other.index.empty() ? 0u : other.index[i]);
}

void PointSet::append(const PointSet& other) {
  if (other.empty()) return;
  const bool first = empty();
  xyz.insert(xyz.end(), other.xyz.begin(), other.xyz.end());
  if (other.has_intensity() && (first || has_intensity()))
    intensity.insert(intensity.end(), other.intensity.begin(), other.intensity.end());
  else
    intensity.clear();
  if (other.has_label() && (first || has_label()))
    label.insert(label.end(), other.label.begin(), other.label.end());
  else
    label.clear();
  if (other.has_changed_against() && (first || has_changed_against()))
    changed_against.insert(changed_against.end(), other.changed_against.begin(), other.changed_against.end());
  else
    changed_against.clear();
  if (other.scan.size() == other.size()) scan.insert(scan.end(), other.scan.begin(), other.scan.end());
  else scan.resize(size(), 0u);
  if (other.index.size() == other.size()) index.insert(index.end(), other.index.begin(), other.index.end());
  else index.resize(size(), 0u);
}

PointSet PointSet::select(const std::vector<uint32_t>& indices) const {
  PointSet out;
  out.xyz.reserve(indices.size());
  const bool keep_scan = scan.size() == size(), keep_index = index.size() == size();
  for (uint32_t i : indices) {
    out.xyz.push_back(xyz[i]);
    if (has_intensity()) out.intensity.push_back(intensity[i]);
    if (has_label()) out.label.push_back(label[i]);
    if (has_changed_against()) out.changed_against.push_back(changed_against[i]);
    out.scan.push_back(keep_scan ? scan[i] : 0u);
    out.index.push_back(keep_index ? index[i] : 0u);
  }
  return out;
}

void PointSet::check_consistent() const {
  const size_t n = size();
  auto bad = [&](const char* what, size_t got) {
    throw Error(std::string("point set has ") + std::to_string(n) + " points but " +
                std::to_string(got) + " " + what + " values");
  };
  if (!intensity.empty() && intensity.size() != n) bad("intensity", intensity.size());
  if (!label.empty() && label.size() != n) bad("label", label.size());
  if (!changed_against.empty() && changed_against.size() != n) bad("changed_against", changed_against.size());
  if (scan.size() != n) bad("scan", scan.size());
  if (index.size() != n) bad("index", index.size());
}

uint8_t PointSet::changed_against_all() const {
  if (!has_changed_against()) return changed_against_either;
  uint8_t bits = 0;
  for (uint8_t b : changed_against) bits |= b;
  return bits & changed_against_either;
}

size_t PointSet::seen_free_count() const {
  return static_cast<size_t>(std::count_if(changed_against.begin(), changed_against.end(),
                                           [](uint8_t b) { return b & seen_free_in_own_mission; }));
}

Eigen::Vector3f PointSet::centroid() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : xyz) sum += p.cast<double>();
  return empty() ? Eigen::Vector3f::Zero() : Eigen::Vector3f((sum / double(size())).cast<float>());
}

void PointSet::bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const {
  if (empty()) {
    min = max = Eigen::Vector3f::Zero();
    return;
  }
  min = max = xyz.front();
  for (const auto& p : xyz) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
}

}  // namespace lista
