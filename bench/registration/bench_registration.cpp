// lista-bench-registration: lista_alignkit's GICP solved by Gauss-Newton
// ("gicp_gn", opt-in in align.posegraph and align.icp) against the same cost
// through PCL's GICP and its BFGS ("gicp", their default), side by side in
// one run.
//
// Scan pairs of a synthetic hall (ray-cast, 16 / 32 / 64 rings), each pair
// one step of the route apart, registered from the true relative pose
// moved by a random offset (up to --offset m and --yaw degrees). Both
// methods see the same clouds, starts and options (coarse then fine stage,
// align.posegraph's scan-to-scan settings); each prepares its clouds
// (k-d trees, covariances) inside the timing, as a pipeline does.
#include <lista_alignkit/cloud_ops.hpp>
#include <lista_alignkit/registration.hpp>
#include <lista_alignkit/synthetic_scene.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace lista::align;
using Clock = std::chrono::steady_clock;

struct Pair {
  Cloud source, target;
  Eigen::Isometry3d truth, guess;  // source -> target
};

struct Outcome {
  std::vector<double> seconds, translation_error, rotation_error_deg;
  size_t converged = 0;
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

Outcome run(const std::vector<Pair>& pairs, RegistrationOptions o, const std::string& method) {
  o.method = method;
  Outcome out;
  for (const Pair& p : pairs) {
    const auto t0 = Clock::now();
    const PreparedCloud source(p.source, o), target(p.target, o);
    const RegistrationResult r = register_prepared(source, target, p.guess, o);
    out.seconds.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    const Eigen::Isometry3d error = p.truth.inverse() * r.transform;
    out.translation_error.push_back(error.translation().norm());
    out.rotation_error_deg.push_back(Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI);
    out.converged += r.converged ? 1 : 0;
  }
  return out;
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
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench registration")) return *code;

  // align.posegraph's scan-to-scan defaults (scan_voxel, scan_coarse_distance,
  // scan_fine_distance, icp_iterations, scan_inlier_distance), without its
  // early refusal after the coarse stage: every pair runs both stages.
  RegistrationOptions o;
  o.voxel = 0.1;
  o.coarse_distance = 1.0;
  o.fine_distance = 0.5;
  o.max_iterations = 40;
  o.inlier_distance = 0.3;

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
    const Outcome stock = run(pairs, o, "gicp");
    const Outcome ours = run(pairs, o, "gicp_gn");
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
