// lista-bench-volumetric: stock OctoMap (insertPointCloud per scan, the
// paper's way) against volumetric.octomap and volumetric.openvdb, on the same
// missions in one run. Each backend runs in a forked child so that its peak
// memory (VmHWM, reset at the child's start) is its own.
//
//   lista-bench-volumetric --dataset DIR [--missions A,B] [--threads 2] [--gt-poses]
//   lista-bench-volumetric --synthetic [--scale 2 --scans-per-position 8]
#include "octomap/volumetric_octomap.hpp"
#include "openvdb/volumetric_openvdb.hpp"
#include "stock_octomap.hpp"
#include <lista_bench/truth_score.hpp>

#include <lista/basic_context.hpp>
#include <lista_io/dataset.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/report.hpp>
#include <lista_raycast/synthetic_scene.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using namespace lista;

namespace {

struct Options {
  std::string dataset, out;
  std::vector<std::string> missions;
  bool synthetic = false;
  bool gt_poses = false;
  raycast::SyntheticSceneConfig scene;
  int threads = 2;
  size_t stock_scans = 0;
  std::vector<std::string> backends = {"stock", "octomap", "openvdb"};
  double resolution = 0.05, max_range = 30.0;
};

// kB value of a /proc/self/status field.
uint64_t proc_status_kb(const char* field) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(f, line))
    if (line.rfind(key, 0) == 0) return std::stoull(line.substr(key.size()));
  return 0;
}

struct Result {
  std::map<std::string, double> num;
  std::vector<std::set<std::pair<uint32_t, uint32_t>>> changed;  // per mission
};

Params params_for(const StageInfo& info, const Options& o) {
  Params p = Params::defaults(info.params);
  p.set("resolution", o.resolution);
  p.set("max_range", o.max_range);
  return p;
}

void write_changes(const std::string& dir, const MissionPoints& ch) {
  fs::create_directories(fs::path(dir) / "changes");
  for (size_t m = 0; m < ch.sets.size(); ++m) {
    const PointSet& s = ch.sets[m];
    std::vector<float> x(s.size()), y(s.size()), z(s.size());
    std::vector<int32_t> object(s.size(), -1);
    for (size_t i = 0; i < s.size(); ++i) {
      x[i] = s.xyz[i].x();
      y[i] = s.xyz[i].y();
      z[i] = s.xyz[i].z();
    }
    io::write_pcd((fs::path(dir) / "changes" / (ch.missions[m] + ".pcd")).string(), s.size(),
                  {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()},
                   {"scan", 'U', s.scan.data()}, {"index", 'U', s.index.data()}, {"object", 'I', object.data()}});
  }
}

// Runs in the child: one backend on all missions; text "key value" lines and
// the changed provenance go to `path`.
void run_backend(const std::string& backend, const MissionSet& missions, const Options& o, const std::string& path) {
  std::ofstream("/proc/self/clear_refs") << "5";  // reset VmHWM to the current RSS
  const double base_kb = static_cast<double>(proc_status_kb("VmRSS"));
  std::ofstream out(path);
  out << std::setprecision(12);
  const auto t0 = std::chrono::steady_clock::now();
  if (backend == "stock") {
    const auto cfg = raycast::volumetric_config(params_for(volumetric::volumetric_octomap_info(), o));
    double seconds = 0, visits = 0, rays = 0, scans = 0;
    for (const Mission& m : missions.missions) {
      // Stock OctoMap takes minutes on a full mission: show where it is on a terminal.
      const StockResult r = run_stock_octomap(m, cfg, o.stock_scans, [&](size_t done, size_t total) {
        if (isatty(STDERR_FILENO))
          std::fprintf(stderr, "\rstock octomap: mission %s, scan %zu/%zu%s", m.name.c_str(), done, total,
                       done == total ? "\n" : "");
      });
      seconds += r.seconds;
      visits += static_cast<double>(r.voxel_visits);
      rays += static_cast<double>(r.rays);
      scans += static_cast<double>(r.scans);
    }
    out << "seconds " << seconds << "\nvoxel_visits " << visits << "\nrays " << rays << "\nscans " << scans << "\n";
  } else {
    const StageInfo info = backend == "octomap" ? volumetric::volumetric_octomap_info() : volumetric::volumetric_openvdb_info();
    const Params p = params_for(info, o);
    auto stage = backend == "octomap" ? volumetric::make_volumetric_octomap(p) : volumetric::make_volumetric_openvdb(p);
    BasicContext ctx("volumetric", o.threads);
    Inputs in;
    in.set("missions", Data::share(std::make_shared<const MissionSet>(missions)));
    Outputs res = stage->run(in, ctx);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const MissionPoints& ch = res.at("changes").as<MissionPoints>();
    double visits = 0, walked = 0, rays = 0, scans = 0;
    for (const Mission& m : missions.missions) scans += static_cast<double>(m.scans.size());
    for (const auto& [k, v] : ctx.info.metrics["volumetric"]) {
      out << "metric." << k << " " << v << "\n";
      if (k.size() > 13 && k.compare(k.size() - 13, 13, ".voxel_visits") == 0) visits += v;
      if (k.size() > 5 && k.compare(k.size() - 5, 5, ".rays") == 0) rays += v;
      if (k.size() > 14 && k.compare(k.size() - 14, 14, ".voxels_walked") == 0) walked += v;
    }
    out << "voxels_walked " << walked << "\n";
    out << "seconds " << seconds << "\nvoxel_visits " << visits << "\nrays " << rays << "\nscans " << scans << "\n";
    for (size_t m = 0; m < ch.sets.size(); ++m) {
      out << "changed " << m << " " << ch.sets[m].size() << "\n";
      for (size_t i = 0; i < ch.sets[m].size(); ++i) out << "p " << m << " " << ch.sets[m].scan[i] << " " << ch.sets[m].index[i] << "\n";
    }
    if (!o.out.empty()) write_changes((fs::path(o.out) / backend).string(), ch);
  }
  out << "peak_extra_mib " << (static_cast<double>(proc_status_kb("VmHWM")) - base_kb) / 1024.0 << "\n";
}

Result run_forked(const std::string& backend, const MissionSet& missions, const Options& o) {
  const std::string path = (fs::temp_directory_path() / ("lista-bench-vol-" + std::to_string(getpid()) + "-" + backend)).string();
  std::cout.flush();
  const pid_t pid = fork();
  if (pid == 0) {
    try {
      run_backend(backend, missions, o, path);
      _exit(0);
    } catch (const std::exception& e) {
      std::cerr << "lista-bench-volumetric: " << backend << ": " << e.what() << "\n";
      _exit(1);
    }
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw Error("backend '" + backend + "' failed");
  Result r;
  r.changed.resize(missions.missions.size());
  std::ifstream in(path);
  std::string key;
  while (in >> key) {
    if (key == "p") {
      size_t m;
      uint32_t s, i;
      in >> m >> s >> i;
      r.changed[m].emplace(s, i);
    } else if (key == "changed") {
      size_t m;
      double n;
      in >> m >> n;
      r.num["changed." + missions.missions[m].name] = n;
    } else {
      in >> r.num[key];
    }
  }
  fs::remove(path);
  return r;
}

double agreement(const Result& a, const Result& b) {
  size_t both = 0, either = 0;
  for (size_t m = 0; m < a.changed.size(); ++m) {
    for (const auto& p : a.changed[m]) both += b.changed[m].count(p);
    either += a.changed[m].size() + b.changed[m].size();
  }
  either -= both;
  return either ? static_cast<double>(both) / either : 1.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Volumetric change detection benchmark: stock OctoMap vs volumetric.octomap vs volumetric.openvdb"};
  Options o;
  std::string missions_csv, backends_csv = "stock,octomap,openvdb";
  app.add_option("--dataset", o.dataset, "lista-sim / contract dataset folder");
  app.add_option("--missions", missions_csv, "comma-separated mission names (default: all, sorted)");
  app.add_flag("--synthetic", o.synthetic, "use the built-in two-room scene instead of a dataset");
  app.add_option("--scale", o.scene.scale, "synthetic: room size factor")->check(lista::cli::between(0.1, 100.0));
  app.add_option("--rings", o.scene.rings, "synthetic: beams per column")->check(CLI::Range(1, 1024));
  app.add_option("--columns", o.scene.columns, "synthetic: columns per revolution")->check(CLI::Range(1, 100000));
  app.add_option("--scans-per-position", o.scene.scans_per_position, "synthetic: scans per sensor spot")
      ->check(CLI::Range(1, 1000));
  app.add_option("--threads", o.threads, "threads for our backends (stock OctoMap is single-threaded)")->check(CLI::Range(1, 256));
  app.add_option("--stock-scans", o.stock_scans, "stock OctoMap: only the first N scans of each mission (0 = all); throughput is extrapolated")
      ->check(lista::cli::at_least(0));
  app.add_option("--backends", backends_csv, "which to run, comma-separated");
  app.add_option("--resolution", o.resolution, "voxel size, m")->check(lista::cli::between(0.005, 10.0));
  // The plugins declare max_range >= 0 (0: none); the bench takes what they take.
  app.add_option("--max-range", o.max_range, "beam range cut, m (0: none)")->check(lista::cli::at_least(0.0));
  app.add_flag("--gt-poses", o.gt_poses, "use poses_gt.txt (true poses, common frame) instead of poses.txt: isolates the volumetric stage from SLAM drift");
  app.add_option("--out", o.out, "write <out>/<backend>/changes/<mission>.pcd (contract format) for lista-eval");
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench volumetric")) return *code;
  try {
    auto split = [](const std::string& s) {
      std::vector<std::string> v;
      std::stringstream ss(s);
      for (std::string t; std::getline(ss, t, ',');)
        if (!t.empty()) v.push_back(t);
      return v;
    };
    o.missions = split(missions_csv);
    o.backends = split(backends_csv);
    if (o.synthetic && !o.dataset.empty())
      throw Error("give either --dataset DIR or --synthetic, not both");
    if (!o.synthetic && o.dataset.empty()) throw Error("give --dataset DIR or --synthetic");

    MissionSet missions;
    std::optional<io::GroundTruth> truth;
    const auto t_load = std::chrono::steady_clock::now();
    if (o.synthetic) {
      missions = raycast::make_synthetic_scene(o.scene);
    } else {
      io::DatasetOptions dopt;
      dopt.missions = o.missions;
      dopt.threads = o.threads;
      missions = io::read_dataset(o.dataset, dopt);
      const fs::path gt = fs::path(o.dataset) / "ground_truth.json";
      if (fs::exists(gt)) {
        truth = io::read_ground_truth(gt.string());
        // The benchmark isolates the volumetric stage: missions are put in the
        // common frame with the true alignment.
        for (Mission& m : missions.missions) {
          auto it = truth->mission_to_world.find(m.name);
          if (it != truth->mission_to_world.end()) m.to_common = Eigen::Isometry3d(it->second);
        }
      }
    }
    if (o.gt_poses) {
      for (Mission& m : missions.missions) {
        if (m.poses_gt.size() != m.scans.size())
          throw Error("--gt-poses: mission '" + m.name + "' has no poses_gt.txt with one pose per scan");
        m.to_common = Eigen::Isometry3d::Identity();
        for (size_t i = 0; i < m.scans.size(); ++i) m.scans[i].pose = m.poses_gt[i];
      }
    }
    size_t points = 0, scans = 0;
    for (const Mission& m : missions.missions) {
      points += m.point_count();
      scans += m.scans.size();
    }
    std::cout << "input: " << (o.synthetic ? std::string("synthetic") : o.dataset) << ", " << missions.missions.size()
              << " missions, " << scans << " scans, " << points << " points (loaded in "
              << std::fixed << std::setprecision(1)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count() << " s)\n"
              << std::setprecision(3) << "resolution " << o.resolution << " m, max_range " << o.max_range << " m, threads " << o.threads
              << " (stock OctoMap: 1)\n\n";

    std::map<std::string, Result> results;
    for (const std::string& b : o.backends) {
      if (b != "stock" && b != "octomap" && b != "openvdb") throw Error("unknown backend '" + b + "'");
      results[b] = run_forked(b, missions, o);
    }

    std::cout << std::left << std::setw(22) << "backend" << std::right << std::setw(8) << "scans" << std::setw(11)
              << "time s" << std::setw(14) << "visits" << std::setw(14) << "Mvisits/s" << std::setw(12) << "peak MiB"
              << std::setw(12) << "changed\n";
    for (const std::string& b : o.backends) {
      auto& n = results[b].num;
      const double vps = n["voxel_visits"] / std::max(1e-9, n["seconds"]);
      double changed = 0;
      for (const auto& m : missions.missions) changed += n["changed." + m.name];
      const std::string name = b == "stock" ? "octomap insertPointCloud" : "volumetric." + b;
      std::cout << std::left << std::setw(22) << name << std::right << std::setw(8) << std::setprecision(0) << n["scans"]
                << std::setw(11) << std::setprecision(2) << n["seconds"] << std::setw(14) << std::setprecision(0)
                << n["voxel_visits"] << std::setw(14) << std::setprecision(2) << vps / 1e6 << std::setw(12)
                << std::setprecision(0) << n["peak_extra_mib"] << std::setw(11)
                << (b == "stock" ? std::string("-") : std::to_string(static_cast<long>(changed))) << "\n";
    }
    auto vps = [&](const std::string& b) { return results[b].num["voxel_visits"] / std::max(1e-9, results[b].num["seconds"]); };
    std::cout << std::setprecision(1);
    if (results.count("stock") && results.count("openvdb"))
      std::cout << "\nthroughput openvdb / stock octomap: " << vps("openvdb") / vps("stock") << "x\n";
    if (results.count("openvdb"))
      std::cout << "volumetric.openvdb stepped through " << 100.0 * results["openvdb"].num["voxels_walked"] /
                       std::max(1.0, results["openvdb"].num["voxel_visits"])
                << " % of the visits (beams stop on free space their scan already counted)\n";
    if (results.count("stock") && results.count("octomap"))
      std::cout << "throughput octomap backend / stock octomap: " << vps("octomap") / vps("stock") << "x\n";
    if (results.count("stock") && results.count("openvdb") && o.stock_scans)
      std::cout << "stock octomap, all scans (extrapolated from visits/s): "
                << results["openvdb"].num["voxel_visits"] / vps("stock") << " s\n";
    if (results.count("octomap") && results.count("openvdb"))
      std::cout << std::setprecision(4) << "agreement octomap vs openvdb (changed points, |both| / |either|): "
                << agreement(results["octomap"], results["openvdb"]) << "\n";

    if (truth || o.synthetic) {
      io::GroundTruth synth;
      if (o.synthetic) {  // labels 1, 2 removed between A and B, 3 added, 4 static
        auto pose = [](double x) { Eigen::Matrix4d m = Eigen::Matrix4d::Identity(); m(0, 3) = x; return m; };
        synth.objects = {{1, "box", false, {{"A", pose(1)}, {"B", std::nullopt}}},
                         {2, "box", false, {{"A", pose(2)}, {"B", std::nullopt}}},
                         {3, "box", false, {{"A", std::nullopt}, {"B", pose(3)}}},
                         {4, "box", false, {{"A", pose(4)}, {"B", pose(4)}}}};
      }
      std::cout << "\nper-point score of the raw volumetric change (all missions):\n";
      for (const std::string& b : o.backends) {
        if (b == "stock") continue;
        const PointScore s = score_points(missions, truth ? *truth : synth, results[b].changed);
        std::cout << "  volumetric." << b << ": precision " << s.precision() << "  recall " << s.recall() << "  F1 "
                  << s.f1() << "  IoU " << s.iou() << "  (TP " << s.tp << " FP " << s.fp << " FN " << s.fn << ")\n";
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "lista-bench-volumetric: error: " << e.what() << "\n";
    return 1;
  }
}
