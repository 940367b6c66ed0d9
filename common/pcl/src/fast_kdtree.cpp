#include <lista_pcl/fast_kdtree.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace lista::pcl_search {

namespace {

// Squared distances are taken in float, x then y then z, as FLANN's L2 does,
// so answers carry the distances PCL's tree gives.
inline float squared_distance(const float* a, const float* b) {
  const float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  float d = dx * dx;
  d += dy * dy;
  d += dz * dz;
  return d;
}

// A query this far out overflows the squared distances (a stray return, a
// corrupt point): it has no neighbour, and is not searched.
bool searchable(const pcl::PointXYZ& p) {
  constexpr float kReach = 1e18f;
  return std::abs(p.x) < kReach && std::abs(p.y) < kReach && std::abs(p.z) < kReach;
}

// One answer: its squared distance and its point of the input cloud.
// Ordered by distance, ties by index, so that an answer never depends on
// the tree's shape.
struct Hit {
  float d2;
  int at;
  bool operator<(const Hit& o) const { return d2 < o.d2 || (d2 == o.d2 && at < o.at); }
};

// The k nearest, kept sorted by insertion (k is small where it is asked).
class Nearest {
 public:
  Nearest(Hit* slots, int k) : slots_(slots), k_(k) {}
  // The bound a subtree must not exceed to hold a better answer.
  float bound() const { return count_ < k_ ? kFar : slots_[k_ - 1].d2; }
  void offer(float d2, int at) {
    const Hit h{d2, at};
    if (count_ == k_ && !(h < slots_[k_ - 1])) return;
    int i = count_ < k_ ? count_++ : k_ - 1;
    for (; i > 0 && h < slots_[i - 1]; --i) slots_[i] = slots_[i - 1];
    slots_[i] = h;
  }
  int count() const { return count_; }

 private:
  static constexpr float kFar = std::numeric_limits<float>::max();
  Hit* slots_;
  int k_;
  int count_ = 0;
};

// The one nearest closer than a bound.
class NearestWithin {
 public:
  explicit NearestWithin(float max_d2) : best_{max_d2, -1} {}
  float bound() const { return best_.d2; }
  void offer(float d2, int at) {
    if (d2 < best_.d2 || (best_.at >= 0 && d2 == best_.d2 && at < best_.at)) best_ = {d2, at};
  }
  const Hit& best() const { return best_; }

 private:
  Hit best_;
};

// Everything closer than a radius.
class Within {
 public:
  Within(float r2, std::vector<Hit>& out) : r2_(r2), out_(out) {}
  float bound() const { return r2_; }
  void offer(float d2, int at) {
    if (d2 < r2_) out_.push_back({d2, at});
  }

 private:
  float r2_;
  std::vector<Hit>& out_;
};

}  // namespace

// A 3-D k-d tree over the finite points, shaped as FLANN's single-index
// tree (a node's box split at the middle of its widest side, leaves of a few
// points stored together) but without its virtual result sets: the search
// is compiled for each kind of question.
struct FastKdTree::Index {
  using Point = std::array<float, 3>;
  static constexpr int kLeafSize = 10;
  struct Node {
    int dim = -1;             // split axis; -1 for a leaf
    float low = 0, high = 0;  // the left child's largest and the right child's smallest coordinate on dim
    int first = 0, last = 0;  // a leaf's points [first, last); an inner node's two children
  };
  std::vector<Point> points;  // leaf by leaf
  std::vector<int> to_cloud;  // their indices in the input cloud
  std::vector<Node> nodes;
  Point box_min{}, box_max{};

  bool empty() const { return points.empty(); }

  Index(std::vector<Point> finite, std::vector<int> cloud_index) {
    std::vector<int> order(finite.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    if (!finite.empty()) split(finite, order, 0, static_cast<int>(order.size()), box_min, box_max);
    points.reserve(order.size());
    to_cloud.reserve(order.size());
    for (int i : order) {
      points.push_back(finite[static_cast<size_t>(i)]);
      to_cloud.push_back(cloud_index[static_cast<size_t>(i)]);
    }
  }

  template <class Answer>
  void search(const float* q, Answer& answer) const {
    Point gaps{};
    float gap2 = 0;
    for (size_t d = 0; d < 3; ++d) {
      const float below = box_min[d] - q[d], above = q[d] - box_max[d];
      gaps[d] = below > 0 ? below * below : above > 0 ? above * above : 0.0f;
      gap2 += gaps[d];
    }
    if (gap2 <= answer.bound()) visit(0, q, gap2, gaps, answer);
  }

 private:
  // Builds the node over order[first, last) and sets its box.
  int split(const std::vector<Point>& p, std::vector<int>& order, int first, int last, Point& lo, Point& hi) {
    lo.fill(std::numeric_limits<float>::max());
    hi.fill(std::numeric_limits<float>::lowest());
    for (int i = first; i < last; ++i)
      for (size_t d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], p[static_cast<size_t>(order[static_cast<size_t>(i)])][d]);
        hi[d] = std::max(hi[d], p[static_cast<size_t>(order[static_cast<size_t>(i)])][d]);
      }
    const int self = static_cast<int>(nodes.size());
    nodes.push_back({-1, 0, 0, first, last});
    if (last - first <= kLeafSize) return self;
    size_t dim = 0;
    for (size_t d = 1; d < 3; ++d)
      if (hi[d] - lo[d] > hi[dim] - lo[dim]) dim = d;
    auto coordinate = [&](int i) { return p[static_cast<size_t>(i)][dim]; };
    const float middle = 0.5f * (lo[dim] + hi[dim]);
    auto begin = order.begin();
    int cut = int(std::partition(begin + first, begin + last, [&](int i) { return coordinate(i) < middle; }) - begin);
    if (cut == first || cut == last) {  // many equal coordinates: halve by count
      cut = first + (last - first) / 2;
      std::nth_element(begin + first, begin + cut, begin + last, [&](int a, int b) { return coordinate(a) < coordinate(b); });
    }
    Point left_lo, left_hi, right_lo, right_hi;
    const int left = split(p, order, first, cut, left_lo, left_hi);
    const int right = split(p, order, cut, last, right_lo, right_hi);
    nodes[static_cast<size_t>(self)] = {static_cast<int>(dim), left_hi[dim], right_lo[dim], left, right};
    return self;
  }

  // gap2: the squared distance from q to the node's box as far as the splits
  // above narrowed it (gaps: per axis); a subtree farther than the answer's
  // bound holds nothing it would take.
  template <class Answer>
  void visit(int at, const float* q, float gap2, Point& gaps, Answer& answer) const {
    const Node& node = nodes[static_cast<size_t>(at)];
    if (node.dim < 0) {
      for (int i = node.first; i < node.last; ++i) {
        const float d2 = squared_distance(q, points[static_cast<size_t>(i)].data());
        if (d2 <= answer.bound()) answer.offer(d2, to_cloud[static_cast<size_t>(i)]);
      }
      return;
    }
    const size_t dim = static_cast<size_t>(node.dim);
    const float below = q[dim] - node.low, above = q[dim] - node.high;
    const bool left_first = below + above < 0;
    visit(left_first ? node.first : node.last, q, gap2, gaps, answer);
    const float cut = left_first ? above * above : below * below, kept = gaps[dim];
    if (gap2 + cut - kept <= answer.bound()) {
      gaps[dim] = cut;
      visit(left_first ? node.last : node.first, q, gap2 + cut - kept, gaps, answer);
      gaps[dim] = kept;
    }
  }
};

FastKdTree::FastKdTree() : Base(true), index_(std::make_unique<Index>(std::vector<Index::Point>(), std::vector<int>())) {}
FastKdTree::~FastKdTree() = default;

void FastKdTree::setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices) {
  input_ = cloud;
  indices_ = indices;
  std::vector<Index::Point> finite;
  std::vector<int> cloud_index;
  const size_t n = !cloud ? 0 : indices ? indices->size() : cloud->size();
  finite.reserve(n);
  cloud_index.reserve(n);
  auto add = [&](int i) {
    const pcl::PointXYZ& p = (*cloud)[static_cast<size_t>(i)];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
    finite.push_back({p.x, p.y, p.z});
    cloud_index.push_back(i);
  };
  if (cloud && indices) {
    for (const auto i : *indices) add(static_cast<int>(i));
  } else if (cloud) {
    for (size_t i = 0; i < cloud->size(); ++i) add(static_cast<int>(i));
  }
  index_ = std::make_unique<Index>(std::move(finite), std::move(cloud_index));
}

int FastKdTree::nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                               std::vector<float>& k_sqr_distances) const {
  k_indices.clear();
  k_sqr_distances.clear();
  if (index_->empty() || k <= 0 || !searchable(point)) return 0;
  if (k == 1 && nearest_bound_ < std::numeric_limits<float>::max()) {
    float d2 = std::numeric_limits<float>::max();
    const int i = nearest(point, d2, nearest_bound_);
    k_indices.push_back(i >= 0 ? i : index_->to_cloud.front());
    k_sqr_distances.push_back(i >= 0 ? d2 : std::numeric_limits<float>::max());
    return 1;
  }
  k = std::min<int>(k, static_cast<int>(index_->to_cloud.size()));
  thread_local std::vector<Hit> slots;
  slots.resize(static_cast<size_t>(k));
  Nearest answer(slots.data(), k);
  const float q[3] = {point.x, point.y, point.z};
  index_->search(q, answer);
  const int found = answer.count();
  k_indices.resize(static_cast<size_t>(found));
  k_sqr_distances.resize(static_cast<size_t>(found));
  for (size_t i = 0; i < static_cast<size_t>(found); ++i) {
    k_indices[i] = slots[i].at;
    k_sqr_distances[i] = slots[i].d2;
  }
  return found;
}

int FastKdTree::radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& k_indices,
                             std::vector<float>& k_sqr_distances, unsigned int max_nn) const {
  k_indices.clear();
  k_sqr_distances.clear();
  if (index_->empty() || !searchable(point)) return 0;
  thread_local std::vector<Hit> hits;
  hits.clear();
  Within answer(static_cast<float>(radius * radius), hits);
  const float q[3] = {point.x, point.y, point.z};
  index_->search(q, answer);
  // Sorted either way: an unsorted answer's order is unspecified.
  size_t n = hits.size();
  if (max_nn > 0 && max_nn < n) {
    n = max_nn;
    std::partial_sort(hits.begin(), hits.begin() + static_cast<std::ptrdiff_t>(n), hits.end());
  } else {
    std::sort(hits.begin(), hits.end());
  }
  k_indices.resize(n);
  k_sqr_distances.resize(n);
  for (size_t i = 0; i < n; ++i) {
    k_indices[i] = hits[i].at;
    k_sqr_distances[i] = hits[i].d2;
  }
  return static_cast<int>(n);
}

int FastKdTree::nearest(const pcl::PointXYZ& point, float& sqr_distance, float max_sqr_distance, int hint) const {
  if (index_->empty() || !searchable(point)) return -1;
  NearestWithin answer(max_sqr_distance);
  const float q[3] = {point.x, point.y, point.z};
  if (hint >= 0) {
    const pcl::PointXYZ& h = (*input_)[static_cast<size_t>(hint)];
    const float at[3] = {h.x, h.y, h.z};
    answer.offer(squared_distance(q, at), hint);
  }
  index_->search(q, answer);
  if (answer.best().at < 0) return -1;
  sqr_distance = answer.best().d2;
  return answer.best().at;
}

}  // namespace lista::pcl_search
