// lista-bench-bagread: how fast a mission is read, and with how much memory,
// as io.missions reads it (a dense log thinned to a scan every 0.5 m). One
// mission per process, so the peak RSS is that mission's: run it on the same
// scene written as folders, ROS 1 and ROS 2 bags, and on bags of different
// lengths, and compare (docs/benchmarks.md).
#include <lista/error.hpp>
#include <lista_bag/bag_mission.hpp>
#include <lista_io/dataset.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sys/resource.h>

int main(int argc, char** argv) {
  CLI::App app{"lista-bench-bagread: read one mission as io.missions does; time, throughput, peak memory"};
  std::string mission;
  double dense_spacing = 0.5;
  app.add_option("mission", mission, "mission folder (scans, a ROS 1 bag or a ROS 2 bag)")->required();
  app.add_option("--dense-spacing", dense_spacing, "io.missions' dense_spacing, m (0 reads every scan)");
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench-bagread")) return *code;
  try {
    lista::io::DatasetOptions opt;
    opt.dense_spacing = dense_spacing;
    lista::bag::BagMissionLog log;
    opt.read_bag_mission = [&](const std::string& dir, const lista::io::DatasetOptions& o) {
      return lista::bag::read_bag_mission(dir, o, {}, &log);
    };
    const auto t0 = std::chrono::steady_clock::now();
    const lista::Mission m = lista::io::read_mission(mission, opt);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    size_t read = 0, kept_points = 0;
    uint64_t all_points = log.cloud_points;
    for (const auto& s : m.scans) {
      read += s.points && !s.points->empty();
      kept_points += s.points ? s.points->size() : 0;
      if (log.bag.empty()) all_points += s.points_in_file;  // a folder: only the scans read are counted
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    uintmax_t bytes = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(mission))
      if (e.is_regular_file()) bytes += e.file_size();
    std::printf("mission     %s (%s)\n", mission.c_str(), log.bag.empty() ? "scan folder" : log.bag.c_str());
    std::printf("scans       %zu, %zu read (dense_spacing %.2g m)\n", m.scans.size(), read, dense_spacing);
    std::printf("points      %llu in the scans read%s, %zu kept\n", (unsigned long long)all_points,
                log.bag.empty() ? "" : " and unread", kept_points);
    std::printf("size        %.1f MB on disk\n", double(bytes) / 1e6);
    std::printf("time        %.2f s: %.2f M points/s, %.0f MB/s\n", seconds, double(all_points) / seconds / 1e6,
                double(bytes) / seconds / 1e6);
    std::printf("peak RSS    %.0f MB\n", double(usage.ru_maxrss) / 1024.0);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lista-bench-bagread: %s\n", e.what());
    return 1;
  }
}
