// lista-bench-registration: lista_alignkit's GICP solved by Gauss-Newton
// ("gicp_gn": align.posegraph's default since 1.8.0, opt-in in align.icp)
// against the same cost through PCL's GICP and its BFGS ("gicp"), side by
// side in one run.
//
// Scan pairs of a synthetic hall (ray-cast, 16 / 32 / 64 rings), each pair
// one step of the route apart, registered from the true relative pose
// moved by a random offset (up to --offset m and --yaw degrees). Or, with
// --dataset, the scan pairs of a recorded dataset with poses_gt.txt, as
// align.posegraph's scan-to-scan edges register them: from the odometry,
// judged by its gates, scored against the truth (the odometry's own error
// is the row to beat). Both methods see the same clouds, starts and
// options (coarse then fine stage, align.posegraph's scan-to-scan
// settings); each prepares its clouds (k-d trees, covariances) inside the
// timing, as a pipeline does.
#include "dataset_pairs.hpp"

#include <lista_alignkit/cloud_ops.hpp>
#include <lista_alignkit/registration.hpp>
#include <lista_alignkit/synthetic_scene.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace lista::alignkit;
using Clock = std::chrono::steady_clock;

using Pair = lista::bench::ScanPair;

// align.posegraph's defaults for its scan-to-scan gates (min_overlap,
// max_rmse, scan_max_plane_rmse).
constexpr double kMinOverlap = 0.5, kMaxRmse = 0.15, kMaxPlaneRmse = 0.06;

struct Outcome {
  std::vector<double> seconds, translation_error, rotation_error_deg;
  // What a planar scan edge keeps (horizontal translation, yaw), over the
  // pairs that pass the gates.
  std::vector<double> passed_horizontal_error, passed_yaw_error_deg;
  // Signed horizontal error along the step (positive: too long), over the
  // passed pairs: a bias here, unlike scatter, adds up along a mission.
  std::vector<double> passed_along_step_error;
  size_t converged = 0, passed = 0;
};

void score(const Pair& p, const Eigen::Isometry3d& estimate, Outcome& out) {
  const Eigen::Isometry3d error = p.truth.inverse() * estimate;
  out.translation_error.push_back(error.translation().norm());
  out.rotation_error_deg.push_back(Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI);
}

void score_passed(const Pair& p, const Eigen::Isometry3d& estimate, Outcome& out) {
  const Eigen::Isometry3d error = p.truth.inverse() * estimate;
  out.passed_horizontal_error.push_back(error.translation().head<2>().norm());
  const Eigen::Vector3d x = error.linear().col(0);
  out.passed_yaw_error_deg.push_back(std::abs(std::atan2(x.y(), x.x())) * 180.0 / M_PI);
  const Eigen::Vector2d step = p.truth.translation().head<2>();
  if (step.norm() > 1e-6)
    out.passed_along_step_error.push_back((estimate.translation().head<2>() - step).dot(step.normalized()));
  ++out.passed;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

// Judged by the gates align.posegraph's scan-to-scan edges use for `method`
// with their defaults (both ways).
Outcome run(const std::vector<Pair>& pairs, RegistrationOptions o, RegistrationMethod method) {
  o.method = method;
  const RegistrationGates gates = scan_pair_gates(method, kMinOverlap, kMaxRmse, kMaxPlaneRmse);
  o.measure_planes = gates.max_plane_rmse > 0.0;
  Outcome out;
  for (const Pair& p : pairs) {
    const auto t0 = Clock::now();
    const PreparedCloud source(p.source, o), target(p.target, o);
    const RegistrationResult r = register_prepared(source, target, p.guess, o);
    out.seconds.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    score(p, r.transform, out);
    out.converged += r.converged ? 1 : 0;
    if (gates.accept(r, p.guess, true)) score_passed(p, r.transform, out);
  }
  return out;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// The odometry as if it were a third method: its errors over every pair.
Outcome odometry_of(const std::vector<Pair>& pairs) {
  Outcome out;
  for (const Pair& p : pairs) {
    score(p, p.guess, out);
    score_passed(p, p.guess, out);
  }
  return out;
}

// align.posegraph's scan-to-scan defaults (scan_voxel, scan_coarse_distance,
// scan_fine_distance, icp_iterations, scan_inlier_distance).
RegistrationOptions scan_edge_options() {
  RegistrationOptions o;
  o.voxel = 0.1;
  o.coarse_distance = 1.0;
  o.fine_distance = 0.5;
  o.max_iterations = 40;
  o.inlier_distance = 0.3;
  return o;
}

// "median / p95" of v, "-" when empty (no pair passed).
std::string median_p95(const std::vector<double>& v, int decimals) {
  return v.empty() ? "-" : fixed(percentile(v, 0.5), decimals) + " / " + fixed(percentile(v, 0.95), decimals);
}

int run_dataset(const std::string& dir, const lista::bench::DatasetPairOptions& po) {
  const std::vector<Pair> pairs = lista::bench::dataset_pairs(dir, po);
  RegistrationOptions o = scan_edge_options();
  // As align.posegraph: a pair whose coarse stage overlaps less than 0.6 of
  // min_overlap is refused there, without the fine stage.
  o.min_coarse_overlap = 0.6 * kMinOverlap;
  std::printf("%zu scan pairs of %s (each scan onto the next %d), started from the odometry, scored against "
              "poses_gt.txt; gates as align.posegraph's scan-to-scan edges (overlap >= %.2f both ways; RMSE <= %.2f m "
              "point to point for gicp, <= %.2f m along planes for gicp_gn); one thread; times include preparing "
              "both clouds\n\n",
              pairs.size(), dir.c_str(), po.steps, kMinOverlap, kMaxRmse, kMaxPlaneRmse);
  std::printf("| method | median (ms) | p95 (ms) | speed-up (median) | converged | pass the gates | error median / p95 "
              "(m, deg) | passed: horizontal error median / p95 (m) | passed: yaw error median / p95 (deg) | passed: "
              "along-step error mean (mm) |\n"
              "|---|---:|---:|---:|---:|---:|---|---|---|---:|\n");
  const Outcome stock = run(pairs, o, RegistrationMethod::gicp);
  const Outcome ours = run(pairs, o, RegistrationMethod::gicp_gn);
  const Outcome odometry = odometry_of(pairs);
  const double stock_median = percentile(stock.seconds, 0.5);
  for (const auto& [name, r] : {std::pair<const char*, const Outcome*>{"odometry (poses.txt)", &odometry},
                                {"PCL GICP (gicp)", &stock},
                                {"Gauss-Newton GICP (gicp_gn)", &ours}}) {
    const bool timed = !r->seconds.empty();  // the odometry is not a registration
    const double median = timed ? percentile(r->seconds, 0.5) : 0.0;
    const std::string ms = timed ? fixed(1e3 * median, 1) : "-", p95 = timed ? fixed(1e3 * percentile(r->seconds, 0.95), 1) : "-",
                      ratio = timed ? fixed(stock_median / median, 2) + "x" : "-",
                      converged = timed ? std::to_string(r->converged) + " / " + std::to_string(pairs.size()) : "-";
    const auto& along = r->passed_along_step_error;
    const std::string bias =
        along.empty() ? "-" : fixed(1e3 * std::accumulate(along.begin(), along.end(), 0.0) / along.size(), 2);
    std::printf("| %s | %s | %s | %s | %s | %zu / %zu | %s, %s | %s | %s | %s |\n", name, ms.c_str(), p95.c_str(),
                ratio.c_str(), converged.c_str(), r->passed, pairs.size(), median_p95(r->translation_error, 4).c_str(),
                median_p95(r->rotation_error_deg, 3).c_str(), median_p95(r->passed_horizontal_error, 4).c_str(),
                median_p95(r->passed_yaw_error_deg, 3).c_str(), bias.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"GICP: lista_alignkit's Gauss-Newton against PCL's BFGS, side by side"};
  int pairs_per_sensor = 40;
  double max_offset = 0.3, max_yaw = 5.0;
  unsigned seed = 1;
  app.add_option("--pairs", pairs_per_sensor, "scan pairs per sensor (16, 32 and 64 rings)")->check(CLI::Range(1, 10000));
  app.add_option("--offset", max_offset, "largest start error, m")->check(CLI::Range(0.0, 5.0));
  app.add_option("--yaw", max_yaw, "largest start yaw error, degrees")->check(CLI::Range(0.0, 90.0));
  app.add_option("--seed", seed, "scene, scans and start errors");
  std::string dataset;
  lista::bench::DatasetPairOptions po;
  app.add_option("--dataset", dataset,
                 "a recorded dataset with poses_gt.txt: its scan pairs from the odometry instead of the synthetic hall")
      ->check(CLI::ExistingDirectory);
  app.add_option("--steps", po.steps, "--dataset: each scan onto the next N scans (align.posegraph's scans.neighbours)")
      ->check(CLI::Range(1, 10));
  app.add_option("--max-pairs", po.max_pairs, "--dataset: at most this many pairs, spread over the dataset (0: all)");
  app.add_option("--threads", po.threads, "--dataset: threads reading the scans")->check(CLI::Range(1, 256));
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench registration")) return *code;
  if (!dataset.empty()) {
    try {
      return run_dataset(dataset, po);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "lista-bench registration: %s\n", e.what());
      return 1;
    }
  }

  // Without align.posegraph's early refusal after the coarse stage: every
  // pair runs both stages.
  const RegistrationOptions o = scan_edge_options();

  constexpr double kHallX = 40.0, kHallY = 24.0;
  const testing::Scene hall = testing::make_hall(kHallX, kHallY, 60, seed);
  const auto route = testing::loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::printf("%d scan pairs per sensor (synthetic hall %.0f x %.0f m, scans 1 m apart), start off by up to "
              "%.2f m and %.1f deg; one thread; times include preparing both clouds\n\n",
              pairs_per_sensor, kHallX, kHallY, max_offset, max_yaw);
  std::printf("| rings | method | median (ms) | p95 (ms) | speed-up (median) | converged | translation error median / p95 (m) | "
              "rotation error median / p95 (deg) |\n|---|---|---:|---:|---:|---:|---|---|\n");
  for (int rings : {16, 32, 64}) {
    std::vector<Pair> pairs;
    for (int k = 0; k < pairs_per_sensor; ++k) {
      const size_t i = static_cast<size_t>(k) * 3 % (route.size() - 1);
      Pair p;
      p.source = voxel_downsample(testing::cast_scan(hall, route[i + 1], 1, rng, rings).xyz, o.voxel);
      p.target = voxel_downsample(testing::cast_scan(hall, route[i], 0, rng, rings).xyz, o.voxel);
      p.truth = route[i].inverse() * route[i + 1];
      Eigen::Isometry3d off = Eigen::Isometry3d::Identity();
      off.translation() = Eigen::Vector3d(unit(rng), unit(rng), 0.2 * unit(rng)) * max_offset;
      off.linear() = Eigen::AngleAxisd(unit(rng) * max_yaw * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      p.guess = p.truth * off;
      pairs.push_back(std::move(p));
    }
    const Outcome stock = run(pairs, o, RegistrationMethod::gicp);
    const Outcome ours = run(pairs, o, RegistrationMethod::gicp_gn);
    const double stock_median = percentile(stock.seconds, 0.5);
    for (const auto& [name, r] : {std::pair<const char*, const Outcome*>{"PCL GICP (gicp)", &stock},
                                  {"Gauss-Newton GICP (gicp_gn)", &ours}}) {
      const double median = percentile(r->seconds, 0.5);
      std::printf("| %d | %s | %.1f | %.1f | %.2fx | %zu / %zu | %.4f / %.4f | %.3f / %.3f |\n", rings, name,
                  1e3 * median, 1e3 * percentile(r->seconds, 0.95), stock_median / median, r->converged, pairs.size(),
                  percentile(r->translation_error, 0.5), percentile(r->translation_error, 0.95),
                  percentile(r->rotation_error_deg, 0.5), percentile(r->rotation_error_deg, 0.95));
    }
  }
  return 0;
}
