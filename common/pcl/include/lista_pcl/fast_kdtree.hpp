// A drop-in pcl::search::KdTree<PointXYZ> for code that searches one point
// at a time (ICP correspondences, GICP covariances, local planes, fitness
// checks).
//
// Why: PCL's precompiled KdTreeFLANN runs FLANN built with OpenMP, and FLANN
// opens an OpenMP parallel region around every query, even a single point
// with one thread: a 1-NN query on 5 000 points costs ~2.8 us instead of
// ~0.35 us, and threads searching at once meet on libgomp's futexes. FLANN's
// search itself goes through virtual result sets. This class is its own
// exact 3-D k-d tree with a search compiled per kind of question (k nearest,
// nearest within a bound, within a radius). Answers are sorted by distance,
// points at equal distance by their index in the cloud, so they do not
// depend on how the tree split the points; distances are FLANN's (float, x
// then y then z). Hand it to PCL with setSearchMethodTarget/Source.
#pragma once

#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <limits>
#include <memory>
#include <vector>

namespace lista::pcl_search {

class FastKdTree : public pcl::search::KdTree<pcl::PointXYZ> {
 public:
  using Ptr = std::shared_ptr<FastKdTree>;
  using Base = pcl::search::KdTree<pcl::PointXYZ>;
  using Base::nearestKSearch;
  using Base::radiusSearch;

  FastKdTree();
  ~FastKdTree() override;

  // Builds the index over `cloud` (or the `indices` subset of it); results
  // name points of `cloud`, as with PCL's trees.
  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override;
  int nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override;
  int radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override;

  // The nearest point closer than sqrt(max_sqr_distance) (its index in the
  // input cloud) and its squared distance, allocation-free; -1 when there is
  // none, the tree is empty or the query too far out to search
  // (sqr_distance is then left as it was). The bound makes the search
  // cheaper, most of all for queries with no point near.
  // `hint`: a point this tree gave as an answer before (an ICP iteration's
  // correspondence, asked again in the next): its distance bounds the search
  // from the start; the answer is the same.
  int nearest(const pcl::PointXYZ& point, float& sqr_distance,
              float max_sqr_distance = std::numeric_limits<float>::max(), int hint = -1) const;

  // Bounds the 1-NN queries of nearestKSearch (k = 1) that PCL's ICP and
  // GICP make for correspondences: set to their max correspondence
  // distance squared, a query with no point that near is answered at once
  // with one point at distance FLT_MAX, which they skip as too far (GICP
  // stops on an empty answer, so one is always given). The rest of their
  // correspondences are the same. FLT_MAX (the default) = unbounded.
  void set_nearest_bound(float max_sqr_distance) { nearest_bound_ = max_sqr_distance; }

 private:
  struct Index;
  std::unique_ptr<Index> index_;
  float nearest_bound_ = std::numeric_limits<float>::max();
};

}  // namespace lista::pcl_search
