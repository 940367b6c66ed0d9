// lista-bench-segmentation: times segment.voxel (voxel and exact modes)
// against stock PCL Euclidean cluster extraction (segment.euclidean) on the
// same synthetic change clouds in one run, checks that exact mode gives PCL's
// clusters, and times the filters. Object recovery (IoU > 0.5 with a true
// object) is shown for each filter chain, as a sanity check of the chain.
// With --changes DIR the clouds are real change points instead: every .pcd
// in DIR (e.g. the changes/ folder a lista-run writes), one per mission.
#include "filter/ground/ground_removal.hpp"
#include "filter/mls/mls_smoothing.hpp"
#include "filter/morphology/morphology.hpp"
#include "segment/euclidean/euclidean_clustering.hpp"
#include <lista_segmentation/voxel_clustering.hpp>
#include "synthetic_changes.hpp"

#include <lista_io/pcd.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>

using namespace lista;
using Clock = std::chrono::steady_clock;

namespace {

// Median wall time of `repeat` runs, in seconds.
double time_it(int repeat, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < repeat; ++r) {
    auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

// True objects (label > 0) recovered by a cluster with IoU > 0.5.
size_t recovered(const std::vector<std::vector<uint32_t>>& clusters, const std::vector<uint32_t>& label,
                 const std::vector<uint32_t>& original_index, const std::map<uint32_t, size_t>& size_of) {
  size_t n = 0;
  for (const auto& c : clusters) {
    std::map<uint32_t, size_t> count;
    for (auto i : c) count[label[original_index[i]]]++;
    for (auto& [id, k] : count)
      if (id != 0) {
        const double iou = double(k) / double(c.size() + size_of.at(id) - k);
        n += iou > 0.5;
      }
  }
  return n;
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"segmentation benchmark: segment.voxel vs PCL Euclidean clustering"};
  bench::SyntheticChangeConfig sc;
  int missions = 3, repeat = 3;
  double tolerance = 0.1;
  bool with_mls = true;
  std::string changes_dir;
  app.add_option("--objects", sc.objects, "objects per mission")->check(CLI::Range(1, 100000));
  app.add_option("--spacing", sc.spacing, "surface sample spacing, m")->check(lista::cli::between(0.005, 1.0));
  app.add_option("--missions", missions, "missions (clouds)")->check(CLI::Range(1, 1000));
  app.add_option("--repeat", repeat, "timed repeats (median reported)")->check(CLI::Range(1, 1000));
  app.add_option("--tolerance", tolerance, "cluster tolerance / voxel, m")->check(lista::cli::between(0.001, 10.0));
  app.add_option("--seed", sc.seed, "seed");
  app.add_flag("!--no-mls", with_mls, "skip the (slow) MLS timing");
  app.add_option("--changes", changes_dir, "folder of real change clouds (*.pcd, one per mission) instead of synthetic ones")
      ->check(CLI::ExistingDirectory);
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench segmentation")) return *code;

  std::vector<PointSet> clouds;
  std::vector<std::vector<uint32_t>> labels;  // synthetic only
  size_t total = 0;
  if (!changes_dir.empty()) {
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(changes_dir))
      if (e.path().extension() == ".pcd") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) {
      std::fprintf(stderr, "lista-bench-segmentation: error: no .pcd files in %s\n", changes_dir.c_str());
      return 2;
    }
    for (uint32_t m = 0; m < files.size(); ++m) {
      clouds.push_back(io::read_scan(files[m], m).points);
      total += clouds.back().size();
    }
    missions = int(clouds.size());
    std::printf("real change clouds from %s: %d missions, %zu points (%.0f per mission), "
                "tolerance %.3f m, one thread, median of %d\n\n",
                changes_dir.c_str(), missions, total, double(total) / missions, tolerance, repeat);
  } else {
    for (int m = 0; m < missions; ++m) {
      auto cfg = sc;
      cfg.seed = sc.seed + uint64_t(m);
      std::vector<uint32_t> label;
      clouds.push_back(bench::synthetic_changes(cfg, &label));
      labels.push_back(std::move(label));
      total += clouds.back().size();
    }
    std::printf("synthetic change clouds: %d missions, %zu points (%.0f per mission), %d objects each, "
                "tolerance %.3f m, one thread, median of %d\n\n",
                missions, total, double(total) / missions, sc.objects, tolerance, repeat);
  }

  segmentation::VoxelClusterConfig vox;
  vox.tolerance = tolerance;
  vox.min_points = 20;
  segmentation::VoxelClusterConfig exact = vox;
  exact.exact = true;
  segment::EuclideanClusterConfig ec;
  ec.tolerance = tolerance;
  ec.min_points = 20;

  size_t n_vox = 0, n_exact = 0, n_pcl = 0;
  bool same = true;
  const double t_vox = time_it(repeat, [&] {
    n_vox = 0;
    for (auto& c : clouds) n_vox += segmentation::cluster_voxels(c.xyz, vox).size();
  });
  const double t_exact = time_it(repeat, [&] {
    n_exact = 0;
    for (auto& c : clouds) n_exact += segmentation::cluster_voxels(c.xyz, exact).size();
  });
  const double t_pcl = time_it(repeat, [&] {
    n_pcl = 0;
    for (auto& c : clouds) n_pcl += segment::cluster_euclidean(c, ec).size();
  });
  for (auto& c : clouds) same &= segmentation::cluster_voxels(c.xyz, exact) == segment::cluster_euclidean(c, ec);

  std::printf("| clustering | time (s) | vs PCL | clusters |\n|---|---|---|---|\n");
  std::printf("| PCL EuclideanClusterExtraction (segment.euclidean) | %.3f | 1.00x | %zu |\n", t_pcl, n_pcl);
  std::printf("| segment.voxel connectivity=exact | %.3f | %.1fx faster | %zu |\n", t_exact, t_pcl / t_exact, n_exact);
  std::printf("| segment.voxel connectivity=voxel (default) | %.3f | %.1fx faster | %zu |\n", t_vox, t_pcl / t_vox, n_vox);
  std::printf("\nexact mode gives PCL's clusters point for point: %s\n\n", same ? "yes" : "NO");

  // Filter timings and the chain's object recovery.
  filter::GroundConfig gc;
  filter::MorphologyConfig mc;
  std::vector<std::vector<uint32_t>> after_ground(clouds.size()), after_morph(clouds.size());
  const double t_ground = time_it(repeat, [&] {
    for (size_t m = 0; m < clouds.size(); ++m) {
      auto g = filter::find_ground(clouds[m], gc, 1);
      std::vector<uint32_t> keep;
      size_t k = 0;
      for (uint32_t i = 0; i < clouds[m].size(); ++i) {
        if (k < g.size() && g[k] == i) { ++k; continue; }
        keep.push_back(i);
      }
      after_ground[m] = keep;
    }
  });
  const double t_morph = time_it(repeat, [&] {
    for (size_t m = 0; m < clouds.size(); ++m) {
      auto sub = clouds[m].select(after_ground[m]);
      auto keep = filter::morphology_keep(sub, mc);
      after_morph[m].clear();
      for (auto i : keep) after_morph[m].push_back(after_ground[m][i]);
    }
  });
  double t_mls = 0;
  if (with_mls)
    t_mls = time_it(1, [&] {
      for (auto& c : clouds) filter::mls_smooth(c, filter::MlsConfig{}, 1);
    });

  size_t truth_objects = 0;
  auto chain = [&](const std::vector<std::vector<uint32_t>>& subsets, double* seconds) {
    size_t found = 0;
    auto t0 = Clock::now();
    for (size_t m = 0; m < clouds.size(); ++m) {
      std::map<uint32_t, size_t> size_of;
      for (auto l : labels[m]) size_of[l]++;
      auto sub = clouds[m].select(subsets[m]);
      found += recovered(segmentation::cluster_voxels(sub.xyz, vox), labels[m], subsets[m], size_of);
    }
    if (seconds) *seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return found;
  };
  std::vector<std::vector<uint32_t>> all(clouds.size());
  for (size_t m = 0; m < clouds.size(); ++m) {
    all[m].resize(clouds[m].size());
    for (uint32_t i = 0; i < clouds[m].size(); ++i) all[m][i] = i;
    truth_objects += size_t(sc.objects);
  }
  std::printf("| filter | time (s) | points left |\n|---|---|---|\n");
  size_t left_g = 0, left_m = 0;
  for (auto& v : after_ground) left_g += v.size();
  for (auto& v : after_morph) left_m += v.size();
  std::printf("| filter.ground | %.3f | %zu of %zu |\n", t_ground, left_g, total);
  std::printf("| filter.morphology (after ground) | %.3f | %zu |\n", t_morph, left_m);
  if (with_mls) std::printf("| filter.mls (radius 0.1) | %.3f | %zu |\n", t_mls, total);
  if (labels.empty()) {  // real clouds: no truth here (score them with lista-eval)
    double t_seg = 0;
    auto t0 = Clock::now();
    size_t n = 0;
    for (size_t m = 0; m < clouds.size(); ++m) n += segmentation::cluster_voxels(clouds[m].select(after_morph[m]).xyz, vox).size();
    t_seg = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf("\nground + morphology + segment.voxel, one thread: %.3f s for %zu points, %zu clusters\n",
                t_ground + t_morph + t_seg, total, n);
    return same ? 0 : 1;
  }
  std::printf("\n| chain before segment.voxel | true objects recovered (IoU > 0.5) |\n|---|---|\n");
  std::printf("| none | %zu of %zu |\n", chain(all, nullptr), truth_objects);
  std::printf("| filter.ground | %zu of %zu |\n", chain(after_ground, nullptr), truth_objects);
  double t_seg = 0;
  std::printf("| filter.ground + filter.morphology | %zu of %zu |\n", chain(after_morph, &t_seg), truth_objects);
  std::printf("\nground + morphology + segment.voxel, one thread: %.3f s for %zu points\n",
              t_ground + t_morph + t_seg, total);
  return same ? 0 : 1;
}

// Bad data (a malformed --changes cloud) is one line and exit 1, not an abort.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lista-bench segmentation: error: %s\n", e.what());
    return 1;
  }
}
