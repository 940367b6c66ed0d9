// Compiled without OpenMP on purpose: FLANN's per-query `omp parallel`
// pragmas then vanish (see fast_kdtree.hpp).
#include <lista_pcl/fast_kdtree.hpp>

// FLANN is header-only templates: hide this library's copies so that they
// neither interpose on PCL's (OpenMP) copies nor get interposed by them; each
// caller then gets the search it asked for, whatever the load order.
#pragma GCC visibility push(hidden)
#include <flann/flann.hpp>
#pragma GCC visibility pop

#include <cmath>

namespace lista::pcl_search {

namespace {
// FLANN computes squared distances in float: a query beyond 1e18 m (a stray
// return, a corrupt point) overflows them to inf, and FLANN then finds no
// neighbour or worse. Such a query has no neighbour: answered without FLANN.
bool searchable(const pcl::PointXYZ& p) {
  constexpr float kReach = 1e18f;
  return std::abs(p.x) < kReach && std::abs(p.y) < kReach && std::abs(p.z) < kReach;
}
}  // namespace

// Hidden like the FLANN type it holds (else GCC warns of a visible struct
// with a hidden field; nothing outside this file sees it anyway).
struct __attribute__((visibility("hidden"))) FastKdTree::Index {
  std::vector<float> xyz;      // packed coordinates of the indexed points
  std::vector<int> to_cloud;   // index position -> point of the input cloud
  std::unique_ptr<flann::KDTreeSingleIndex<flann::L2_Simple<float>>> tree;
};

FastKdTree::FastKdTree() : Base(true), index_(std::make_unique<Index>()) {}
FastKdTree::~FastKdTree() = default;

void FastKdTree::setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices) {
  input_ = cloud;
  indices_ = indices;
  auto next = std::make_unique<Index>();
  auto add = [&](int i) {
    const pcl::PointXYZ& p = (*cloud)[static_cast<size_t>(i)];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
    next->xyz.insert(next->xyz.end(), {p.x, p.y, p.z});
    next->to_cloud.push_back(i);
  };
  if (cloud) {
    if (indices) {
      for (const auto i : *indices) add(static_cast<int>(i));
    } else {
      for (size_t i = 0; i < cloud->size(); ++i) add(static_cast<int>(i));
    }
  }
  if (!next->to_cloud.empty()) {
    flann::Matrix<float> data(next->xyz.data(), next->to_cloud.size(), 3);
    next->tree = std::make_unique<flann::KDTreeSingleIndex<flann::L2_Simple<float>>>(
        data, flann::KDTreeSingleIndexParams(15));
    next->tree->buildIndex();
  }
  index_ = std::move(next);
}

int FastKdTree::nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                               std::vector<float>& k_sqr_distances) const {
  k_indices.clear();
  k_sqr_distances.clear();
  if (!index_->tree || k <= 0 || !searchable(point)) return 0;
  if (k == 1 && nearest_bound_ < std::numeric_limits<float>::max()) {
    float d2 = std::numeric_limits<float>::max();
    const int i = nearest(point, d2, nearest_bound_);
    k_indices.push_back(i >= 0 ? i : index_->to_cloud.front());
    k_sqr_distances.push_back(i >= 0 ? d2 : std::numeric_limits<float>::max());
    return 1;
  }
  k = std::min<int>(k, static_cast<int>(index_->to_cloud.size()));
  std::vector<int> idx(static_cast<size_t>(k));
  k_sqr_distances.resize(static_cast<size_t>(k));
  float q[3] = {point.x, point.y, point.z};
  flann::Matrix<int> mi(idx.data(), 1, static_cast<size_t>(k));
  flann::Matrix<float> md(k_sqr_distances.data(), 1, static_cast<size_t>(k));
  flann::SearchParams params(-1, 0.0f, true);
  index_->tree->knnSearch(flann::Matrix<float>(q, 1, 3), mi, md, static_cast<size_t>(k), params);
  // FLANN leaves -1 where it found no neighbour (a query whose squared
  // distances overflow float): return only what it found.
  int found = 0;
  while (found < k && idx[static_cast<size_t>(found)] >= 0) ++found;
  k_indices.resize(static_cast<size_t>(found));
  k_sqr_distances.resize(static_cast<size_t>(found));
  for (int i = 0; i < found; ++i)
    k_indices[static_cast<size_t>(i)] = index_->to_cloud[static_cast<size_t>(idx[static_cast<size_t>(i)])];
  return found;
}

int FastKdTree::radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& k_indices,
                             std::vector<float>& k_sqr_distances, unsigned int max_nn) const {
  k_indices.clear();
  k_sqr_distances.clear();
  if (!index_->tree || !searchable(point)) return 0;
  std::vector<std::vector<int>> idx(1);
  std::vector<std::vector<float>> dist(1);
  float q[3] = {point.x, point.y, point.z};
  flann::SearchParams params(-1, 0.0f, sorted_results_);
  if (max_nn > 0) params.max_neighbors = static_cast<int>(max_nn);
  index_->tree->radiusSearch(flann::Matrix<float>(q, 1, 3), idx, dist, static_cast<float>(radius * radius), params);
  k_indices.reserve(idx[0].size());
  for (int i : idx[0]) k_indices.push_back(index_->to_cloud[static_cast<size_t>(i)]);
  k_sqr_distances = std::move(dist[0]);
  return static_cast<int>(k_indices.size());
}

namespace {
// FLANN result set for the one nearest point within a bound: the bound
// prunes the search from the start, where an unbounded 1-NN query walks
// far for a point with no neighbour near (most of a scan's points outside
// the overlap).
class __attribute__((visibility("hidden"))) NearestWithin : public flann::ResultSet<float> {
 public:
  explicit NearestWithin(float max_sqr_distance) : best_(max_sqr_distance) {}
  bool full() const override { return true; }
  float worstDist() const override { return best_; }
  void addPoint(float dist, size_t index) override {
    if (dist < best_) best_ = dist, index_ = index;
  }
  bool found() const { return index_ != kNone; }
  size_t index() const { return index_; }
  float distance() const { return best_; }

 private:
  static constexpr size_t kNone = static_cast<size_t>(-1);
  float best_;
  size_t index_ = kNone;
};
}  // namespace

int FastKdTree::nearest(const pcl::PointXYZ& point, float& sqr_distance, float max_sqr_distance) const {
  if (!index_->tree || !searchable(point)) return -1;
  NearestWithin result(max_sqr_distance);
  const float q[3] = {point.x, point.y, point.z};
  index_->tree->findNeighbors(result, q, flann::SearchParams(-1, 0.0f, false));
  if (!result.found()) return -1;
  sqr_distance = result.distance();
  return index_->to_cloud[result.index()];
}

}  // namespace lista::pcl_search
