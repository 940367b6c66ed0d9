// FastKdTree must answer exactly as PCL's KdTreeFLANN, points at equal
// distance ranked by index (it replaces it inside PCL's ICP/GICP,
// clustering and MLS), and work as their search method.
#include <lista_pcl/fast_kdtree.hpp>

#include <gtest/gtest.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <algorithm>
#include <limits>
#include <random>
#include <utility>

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

Cloud::Ptr random_cloud(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Cloud::Ptr c(new Cloud);
  for (size_t i = 0; i < n; ++i) c->push_back(pcl::PointXYZ(u(rng), u(rng), u(rng)));
  return c;
}

// `cloud` moved by (0.03, -0.02, 0.01): the source the ICP tests register back.
Cloud::Ptr shifted(const Cloud& cloud) {
  Eigen::Affine3f shift = Eigen::Affine3f::Identity();
  shift.translation() << 0.03f, -0.02f, 0.01f;
  Cloud::Ptr moved(new Cloud);
  pcl::transformPointCloud(cloud, *moved, shift);
  return moved;
}

// Both trees over the same random cloud.
struct Trees {
  explicit Trees(unsigned seed) : cloud(random_cloud(2000, seed)) {
    fast.setInputCloud(cloud);
    stock.setInputCloud(cloud);
  }
  Cloud::Ptr cloud;
  lista::pcl_search::FastKdTree fast;
  pcl::KdTreeFLANN<pcl::PointXYZ> stock;
};

TEST(FastKdTree, KnnMatchesKdTreeFlann) {
  Trees t(1);
  auto& [cloud, fast, stock] = t;
  const Cloud::Ptr queries = random_cloud(300, 2);
  for (const auto& q : queries->points) {
    pcl::Indices fi, si;
    std::vector<float> fd, sd;
    ASSERT_EQ(fast.nearestKSearch(q, 5, fi, fd), 5);
    ASSERT_EQ(stock.nearestKSearch(q, 5, si, sd), 5);
    EXPECT_EQ(fi, si);
    for (size_t k = 0; k < 5; ++k) EXPECT_FLOAT_EQ(fd[k], sd[k]);
    float nearest = -1.0f;
    EXPECT_EQ(fast.nearest(q, nearest), si[0]);
    EXPECT_FLOAT_EQ(nearest, sd[0]);
  }
}

TEST(FastKdTree, BoundedNearestIsTheNearestWithinTheBound) {
  // nearest() is what GICP asks per point and iteration: the stock 1-NN
  // when it lies within the bound, nothing otherwise; the index names the
  // point of the input cloud.
  Trees t(11);
  auto& [cloud, fast, stock] = t;
  const Cloud::Ptr queries = random_cloud(400, 12);
  size_t within = 0, beyond = 0;
  for (const auto& q : queries->points) {
    pcl::Indices si;
    std::vector<float> sd;
    ASSERT_EQ(stock.nearestKSearch(q, 1, si, sd), 1);
    float d2 = -1.0f;
    EXPECT_EQ(fast.nearest(q, d2), si[0]);
    EXPECT_FLOAT_EQ(d2, sd[0]);
    const float bound = 0.0064f;  // (8 cm)^2: about 40 % of the queries have a point that near
    float bounded = -1.0f;
    const int j = fast.nearest(q, bounded, bound);
    if (sd[0] < bound) {
      ++within;
      EXPECT_EQ(j, si[0]);
      EXPECT_FLOAT_EQ(bounded, sd[0]);
    } else {
      ++beyond;
      EXPECT_EQ(j, -1);
      EXPECT_FLOAT_EQ(bounded, -1.0f) << "left as it was";
    }
  }
  EXPECT_GT(within, 50u);
  EXPECT_GT(beyond, 50u);
  float d2 = 0.0f;
  EXPECT_EQ(fast.nearest(pcl::PointXYZ(1e20f, 0, 0), d2), -1);
}

TEST(FastKdTree, AHintBoundsTheSearchWithoutChangingTheAnswer) {
  // Any indexed point as the hint, near or beyond the bound: the same
  // nearest point (ties included: the grid below has every point twice).
  Trees t(13);
  Cloud::Ptr twice(new Cloud(*t.cloud));
  *twice += *t.cloud;
  lista::pcl_search::FastKdTree fast;
  fast.setInputCloud(twice);
  const Cloud::Ptr queries = random_cloud(300, 14);
  std::mt19937 rng(15);
  std::uniform_int_distribution<int> any(0, static_cast<int>(twice->size()) - 1);
  size_t found = 0;
  for (const auto& q : queries->points)
    for (const float bound : {0.01f, std::numeric_limits<float>::max()}) {
      float plain = -1.0f;
      const int j = fast.nearest(q, plain, bound);
      for (const int hint : {any(rng), j}) {
        if (hint < 0) continue;
        float hinted = -1.0f;
        EXPECT_EQ(fast.nearest(q, hinted, bound, hint), j);
        if (j >= 0) EXPECT_EQ(hinted, plain);
      }
      found += j >= 0;
    }
  EXPECT_GT(found, 350u);
  EXPECT_LT(found, 600u);
}

TEST(FastKdTree, RadiusMatchesKdTreeFlann) {
  Trees t(3);
  auto& [cloud, fast, stock] = t;
  const Cloud::Ptr queries = random_cloud(100, 4);
  for (const auto& q : queries->points) {
    pcl::Indices fi, si;
    std::vector<float> fd, sd;
    const int n = fast.radiusSearch(q, 0.2, fi, fd);
    ASSERT_EQ(n, stock.radiusSearch(q, 0.2, si, sd));
    EXPECT_EQ(fi, si);
    EXPECT_EQ(fast.radiusSearch(q, 0.2, fi, fd, 3), std::min(n, 3));
  }
}

// The squared distance as FastKdTree takes it (FLANN's: float, x, y, z).
float squared(const pcl::PointXYZ& a, const pcl::PointXYZ& b) {
  const float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  float d = dx * dx;
  d += dy * dy;
  d += dz * dz;
  return d;
}

// Every point of `cloud` closer than `r2` to q, by distance, then index.
std::vector<std::pair<float, int>> brute_force(const Cloud& cloud, const pcl::PointXYZ& q, float r2) {
  std::vector<std::pair<float, int>> out;
  for (size_t i = 0; i < cloud.size(); ++i)
    if (const float d = squared(cloud[i], q); d < r2) out.emplace_back(d, static_cast<int>(i));
  std::sort(out.begin(), out.end());
  return out;
}

TEST(FastKdTree, TiesRankByIndexWhateverTheTreeShape) {
  // A grid with every point twice: every query meets ties, which are ranked
  // by index, so the answer is the brute force's to the last index.
  Cloud::Ptr grid(new Cloud);
  for (int copy = 0; copy < 2; ++copy)
    for (int x = 0; x < 8; ++x)
      for (int y = 0; y < 6; ++y)
        for (int z = 0; z < 5; ++z) grid->push_back(pcl::PointXYZ(0.1f * x, 0.1f * y, 0.1f * z));
  lista::pcl_search::FastKdTree fast;
  fast.setInputCloud(grid);
  std::vector<pcl::PointXYZ> queries;
  for (int i = 0; i < 40; ++i) queries.emplace_back(0.05f * (i % 9), 0.1f * (i % 7) - 0.05f * (i % 2), 0.1f * (i % 5));
  for (const auto& q : queries) {
    const auto all = brute_force(*grid, q, std::numeric_limits<float>::max());
    pcl::Indices idx;
    std::vector<float> d2;
    for (int k : {1, 2, 7, 30}) {
      ASSERT_EQ(fast.nearestKSearch(q, k, idx, d2), k);
      for (size_t j = 0; j < static_cast<size_t>(k); ++j) {
        EXPECT_EQ(idx[j], all[j].second) << "k " << k << " rank " << j;
        EXPECT_EQ(d2[j], all[j].first);
      }
    }
    float nearest = -1.0f;
    EXPECT_EQ(fast.nearest(q, nearest), all[0].second);
    const auto within = brute_force(*grid, q, 0.15f * 0.15f);
    ASSERT_EQ(fast.radiusSearch(q, 0.15, idx, d2), static_cast<int>(within.size()));
    for (size_t j = 0; j < within.size(); ++j) EXPECT_EQ(idx[j], within[j].second);
    const int capped = std::min<int>(5, static_cast<int>(within.size()));
    ASSERT_EQ(fast.radiusSearch(q, 0.15, idx, d2, 5), capped);
    for (size_t j = 0; j < static_cast<size_t>(capped); ++j) EXPECT_EQ(idx[j], within[j].second);
  }
}

TEST(FastKdTree, IndicesSubsetAnswersInCloudPositions) {
  const Cloud::Ptr cloud = random_cloud(500, 5);
  auto odd = std::make_shared<pcl::Indices>();
  for (int i = 1; i < 500; i += 2) odd->push_back(i);
  lista::pcl_search::FastKdTree fast;
  fast.setInputCloud(cloud, odd);
  pcl::Indices idx;
  std::vector<float> d2;
  ASSERT_EQ(fast.nearestKSearch((*cloud)[2], 1, idx, d2), 1);
  EXPECT_EQ(idx[0] % 2, 1);  // the even query point itself is not indexed
  ASSERT_EQ(fast.nearestKSearch((*cloud)[7], 1, idx, d2), 1);
  EXPECT_EQ(idx[0], 7);
  EXPECT_FLOAT_EQ(d2[0], 0.0f);
}

TEST(FastKdTree, EmptyTreeFindsNothing) {
  lista::pcl_search::FastKdTree fast;
  fast.setInputCloud(Cloud::Ptr(new Cloud));
  pcl::Indices idx;
  std::vector<float> d2;
  EXPECT_EQ(fast.nearestKSearch(pcl::PointXYZ(0, 0, 0), 3, idx, d2), 0);
  EXPECT_EQ(fast.radiusSearch(pcl::PointXYZ(0, 0, 0), 1.0, idx, d2), 0);
  float nearest = 0.0f;
  EXPECT_EQ(fast.nearest(pcl::PointXYZ(0, 0, 0), nearest), -1);
}

// A query so far out that its squared distances overflow float (a stray
// return at 1e20 m) has no neighbour: none comes back, and FLANN, which then
// returned index -1 or crashed now and then, is not asked.
TEST(FastKdTree, OverflowingQueryFindsNoNeighbour) {
  Trees t(7);
  pcl::Indices idx;
  std::vector<float> d2;
  for (const pcl::PointXYZ far : {pcl::PointXYZ(1e20f, 0, 0), pcl::PointXYZ(0, -3e19f, 1)}) {
    EXPECT_EQ(t.fast.nearestKSearch(far, 3, idx, d2), 0);
    EXPECT_TRUE(idx.empty() && d2.empty());
    EXPECT_EQ(t.fast.radiusSearch(far, 1.0, idx, d2), 0);
    float nearest = 0.0f;
    EXPECT_EQ(t.fast.nearest(far, nearest), -1);
  }
  EXPECT_EQ(t.fast.nearestKSearch(pcl::PointXYZ(0, 0, 0), 3, idx, d2), 3) << "near queries unchanged";
}

TEST(FastKdTree, ServesAsIcpSearchMethod) {
  const Cloud::Ptr target = random_cloud(1500, 6);
  const Cloud::Ptr source = shifted(*target);
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setSearchMethodTarget(std::make_shared<lista::pcl_search::FastKdTree>());
  icp.setInputSource(source);
  icp.setInputTarget(target);
  icp.setMaximumIterations(50);
  Cloud aligned;
  icp.align(aligned);
  ASSERT_TRUE(icp.hasConverged());
  const Eigen::Vector3f t = icp.getFinalTransformation().topRightCorner<3, 1>();
  EXPECT_NEAR(t.x(), -0.03f, 1e-3);
  EXPECT_NEAR(t.y(), 0.02f, 1e-3);
  EXPECT_NEAR(t.z(), -0.01f, 1e-3);
}

TEST(FastKdTree, BoundedOneNearestAnswersAsUnboundedWithinTheBound) {
  Trees t(7);
  t.fast.set_nearest_bound(0.05f * 0.05f);
  const Cloud::Ptr queries = random_cloud(500, 8);
  int near = 0;
  for (const auto& q : *queries) {
    pcl::Indices bi, si;
    std::vector<float> bd, sd;
    ASSERT_EQ(t.fast.nearestKSearch(q, 1, bi, bd), 1);
    t.stock.nearestKSearch(q, 1, si, sd);
    if (sd[0] < 0.05f * 0.05f) {
      EXPECT_EQ(bi[0], si[0]);
      EXPECT_FLOAT_EQ(bd[0], sd[0]);
      ++near;
    } else {
      EXPECT_EQ(bd[0], std::numeric_limits<float>::max());  // beyond the bound: skipped by ICP
    }
  }
  EXPECT_GT(near, 10);
  EXPECT_LT(near, 490);
  // k > 1 is not bounded.
  pcl::Indices bi;
  std::vector<float> bd;
  EXPECT_EQ(t.fast.nearestKSearch(pcl::PointXYZ(5.f, 5.f, 5.f), 3, bi, bd), 3);
}

TEST(FastKdTree, BoundedTreesLeaveIcpAndGicpWhereUnboundedOnesDo) {
  // Half the source has no partner (a partial view): the gate rejects it
  // either way; with the bound its queries stop early.
  const Cloud::Ptr target = random_cloud(1500, 9);
  const Cloud::Ptr source = shifted(*target);
  const Cloud::Ptr unpartnered = random_cloud(700, 10);
  for (const auto& p : *unpartnered) source->push_back(pcl::PointXYZ(p.x + 3.f, p.y, p.z));
  auto register_with = [&](auto& reg, float bound) {
    auto tree = std::make_shared<lista::pcl_search::FastKdTree>();
    tree->set_nearest_bound(bound);
    reg.setSearchMethodTarget(tree);
    reg.setInputSource(source);
    reg.setInputTarget(target);
    reg.setMaxCorrespondenceDistance(0.2);
    reg.setMaximumIterations(30);
    Cloud aligned;
    reg.align(aligned);
    EXPECT_TRUE(reg.hasConverged());
    return Eigen::Matrix4f(reg.getFinalTransformation());
  };
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp_a, icp_b;
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp_a, gicp_b;
  const float unbounded = std::numeric_limits<float>::max();
  EXPECT_TRUE(register_with(icp_a, unbounded).isApprox(register_with(icp_b, 0.2f * 0.2f), 1e-6f));
  const Eigen::Matrix4f g = register_with(gicp_b, 0.2f * 0.2f);
  EXPECT_TRUE(register_with(gicp_a, unbounded).isApprox(g, 1e-6f));
  EXPECT_NEAR(g(0, 3), -0.03f, 2e-3);
}

}  // namespace
