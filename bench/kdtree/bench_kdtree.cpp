// lista-bench-kdtree: why LiSTA hands PCL its own k-d tree.
//
// PCL's precompiled KdTreeFLANN runs FLANN built with OpenMP, which opens a
// parallel region around every query. Code that asks one point at a time
// (ICP correspondences, GICP covariances, fitness checks) pays that on every
// call. This program times the same work with PCL's tree and with
// lista_pcl's FastKdTree in one run and prints the ratios.
#include <lista_pcl/fast_kdtree.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>
#include <pcl/common/transforms.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Clock = std::chrono::steady_clock;

// Points on the faces of a 1 x 0.6 x 0.8 m box (a surface, like a scan).
Cloud::Ptr box_surface(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.003f);
  Cloud::Ptr c(new Cloud);
  const float size[3] = {1.0f, 0.6f, 0.8f};
  for (size_t i = 0; i < n; ++i) {
    const int face = static_cast<int>(i % 6), axis = face / 2;
    float p[3] = {u(rng) * size[0], u(rng) * size[1], u(rng) * size[2]};
    p[axis] = (face % 2) * size[axis];
    c->push_back(pcl::PointXYZ(p[0] + noise(rng), p[1] + noise(rng), p[2] + noise(rng)));
  }
  return c;
}

template <class Tree>
double time_queries(const Tree& tree, const Cloud& queries, int threads, int repeats, int k = 1) {
  const auto t0 = Clock::now();
  std::vector<std::thread> pool;
  std::vector<double> sums(static_cast<size_t>(threads), 0.0);
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      pcl::Indices idx(static_cast<size_t>(k));
      std::vector<float> d2(static_cast<size_t>(k));
      for (int r = 0; r < repeats; ++r)
        for (const auto& q : queries.points)
          if (tree.nearestKSearch(q, k, idx, d2) > 0) sums[static_cast<size_t>(t)] += d2[0];
    });
  for (auto& th : pool) th.join();
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

template <class Reg>
double time_registration(Reg& reg, const Cloud::Ptr& source, const Cloud::Ptr& target, int repeats) {
  const auto t0 = Clock::now();
  for (int r = 0; r < repeats; ++r) {
    reg.setInputSource(source);
    reg.setInputTarget(target);
    reg.setMaximumIterations(30);
    reg.setMaxCorrespondenceDistance(0.1);
    Cloud aligned;
    reg.align(aligned);
  }
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void row(const char* what, double stock, double fast) {
  std::printf("| %s | %.3f | %.3f | %.1fx |\n", what, stock, fast, stock / fast);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"FastKdTree vs PCL KdTreeFLANN, side by side"};
  size_t points = 20000, queries = 20000;
  int repeats = 10;
  app.add_option("--points", points, "indexed points (a box surface)")->check(CLI::Range(size_t{1}, size_t{100000000}));
  app.add_option("--queries", queries, "queries per pass")->check(CLI::Range(size_t{1}, size_t{100000000}));
  app.add_option("--repeats", repeats, "passes per timing")->check(CLI::Range(1, 100000));
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench kdtree")) return *code;

  // A LiSTA run has used OpenMP (volumetric ray casting) before ICP runs:
  // start libgomp's thread pool the same way.
  double warm = 0.0;
#pragma omp parallel for reduction(+ : warm)
  for (int i = 0; i < 1000; ++i) warm += std::sqrt(static_cast<double>(i));
  if (warm < 0.0) return 1;

  const Cloud::Ptr cloud = box_surface(points, 1), probe = box_surface(queries, 2);
  pcl::KdTreeFLANN<pcl::PointXYZ> stock;
  lista::pcl_search::FastKdTree fast;
  auto t0 = Clock::now();
  stock.setInputCloud(cloud);
  const double build_stock = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  fast.setInputCloud(cloud);
  const double build_fast = std::chrono::duration<double>(Clock::now() - t0).count();

  std::printf("%zu points, %zu queries x %d passes, one query per call\n\n", points, queries, repeats);
  std::printf("| work | PCL KdTreeFLANN (s) | FastKdTree (s) | speed-up |\n|---|---:|---:|---:|\n");
  row("build", build_stock, build_fast);
  row("1 nearest, 1 thread", time_queries(stock, *probe, 1, repeats), time_queries(fast, *probe, 1, repeats));
  row("1 nearest, 2 threads (each all)", time_queries(stock, *probe, 2, repeats), time_queries(fast, *probe, 2, repeats));
  // A local plane's neighbourhood (the GICP covariances' question).
  row("10 nearest, 1 thread", time_queries(stock, *probe, 1, repeats, 10), time_queries(fast, *probe, 1, repeats, 10));

  // Registration: the source is the target turned 4 degrees and shifted 3 cm.
  Eigen::Affine3f motion = Eigen::Affine3f::Identity();
  motion.rotate(Eigen::AngleAxisf(0.07f, Eigen::Vector3f::UnitZ()));
  motion.translation() << 0.03f, -0.02f, 0.0f;
  const Cloud::Ptr small = box_surface(3000, 3);
  Cloud::Ptr moved(new Cloud);
  pcl::transformPointCloud(*small, *moved, motion);
  const int reg_repeats = std::max(1, repeats / 2);
  {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> a, b;
    b.setSearchMethodTarget(std::make_shared<lista::pcl_search::FastKdTree>());
    row("PCL ICP, 3000 points, 30 iterations", time_registration(a, moved, small, reg_repeats),
        time_registration(b, moved, small, reg_repeats));
  }
  {
    pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> a, b;
    b.setSearchMethodSource(std::make_shared<lista::pcl_search::FastKdTree>());
    b.setSearchMethodTarget(std::make_shared<lista::pcl_search::FastKdTree>());
    row("PCL GICP, 3000 points, 30 iterations", time_registration(a, moved, small, reg_repeats),
        time_registration(b, moved, small, reg_repeats));
  }

  // A partial view's registration at a poor start, as object pairs meet
  // it: most source points have no target point within the gate. Bounded
  // to the gate (FastKdTree::set_nearest_bound), their queries stop early;
  // the correspondences are the same.
  Cloud::Ptr partial(new Cloud(*moved));
  for (const auto& p : box_surface(9000, 4)->points) partial->push_back(pcl::PointXYZ(p.x + 2.0f, p.y, p.z));
  const float gate = 0.1f * 0.1f;
  std::printf("\nA source of 3000 points with partners and 9000 without (a partial view), gate 0.1 m:\n\n");
  std::printf("| work | FastKdTree (s) | bounded to the gate (s) | speed-up |\n|---|---:|---:|---:|\n");
  {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> a, b;
    a.setSearchMethodTarget(std::make_shared<lista::pcl_search::FastKdTree>());
    auto bounded = std::make_shared<lista::pcl_search::FastKdTree>();
    bounded->set_nearest_bound(gate);
    b.setSearchMethodTarget(bounded);
    row("PCL ICP, 30 iterations", time_registration(a, partial, small, reg_repeats),
        time_registration(b, partial, small, reg_repeats));
  }
  {
    pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> a, b;
    a.setSearchMethodSource(std::make_shared<lista::pcl_search::FastKdTree>());
    a.setSearchMethodTarget(std::make_shared<lista::pcl_search::FastKdTree>());
    auto bounded = std::make_shared<lista::pcl_search::FastKdTree>();
    bounded->set_nearest_bound(gate);
    b.setSearchMethodSource(std::make_shared<lista::pcl_search::FastKdTree>());
    b.setSearchMethodTarget(bounded);
    row("PCL GICP, 30 iterations", time_registration(a, partial, small, reg_repeats),
        time_registration(b, partial, small, reg_repeats));
  }
  return 0;
}
