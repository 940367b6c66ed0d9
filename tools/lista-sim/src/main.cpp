// lista-sim: simulated multi-mission LiDAR datasets with object-level change
// ground truth (data contract, sect. 1 and 3), and single-object views.
#include "dataset_writer.hpp"
#include "furniture.hpp"
#include "presets.hpp"
#include "scenario.hpp"
#include "sensor.hpp"
#include "views.hpp"

#include <lista/error.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>

#include <cstdio>
#include <iostream>
#include <thread>
#include <unistd.h>

namespace {

int default_threads() { return int(std::max(1u, std::thread::hardware_concurrency())); }

// Sweet Home 3D furniture from `folder`, reporting what could not be read.
std::vector<lista::sim::Shape> furniture_from(const std::string& folder, const char* who) {
  std::vector<std::string> skipped;
  std::vector<lista::sim::Shape> shapes = lista::sim::load_furniture(folder, &skipped);
  std::fprintf(stderr, "%s: %zu furniture shapes from %s (%zu models could not be read)\n", who, shapes.size(),
               folder.c_str(), skipped.size());
  for (const auto& why : skipped) std::fprintf(stderr, "  skipped: %s\n", why.c_str());
  return shapes;
}

int run_dataset(const std::string& preset_name, const std::string& out, uint64_t seed, int missions,
                int scans, const std::string& sensor_name, int threads, bool overwrite, const std::string& furniture,
                bool body, const std::vector<std::string>& effects, double drift, double map_tilt, int people,
                bool station_operator, const std::string& format, bool skew, double spin) {
  using namespace lista::sim;
  Preset preset = make_preset(preset_name);
  // Real furniture beside the procedural classes: about a third of the
  // objects drawn (scenario.cpp), scenes no procedural generator made.
  if (!furniture.empty()) preset.changes.extra_shapes = furniture_from(furniture, "lista-sim");
  if (missions > 0) preset.route.missions = missions;
  if (scans > 0) preset.route.scans = scans;
  if (people >= 0) preset.changes.people = people;
  preset.changes.station_operator = station_operator;
  preset.route.drift_per_m *= drift;
  preset.route.yaw_drift_deg_per_m *= drift;
  preset.route.map_tilt_deg = map_tilt;
  preset.route.spin_deg_per_s = spin;
  int columns = preset.columns;
  if (!sensor_name.empty() && sensor_name != preset.sensor) {
    preset.sensor = sensor_name;
    columns = 0;  // the preset's column count belongs to its own sensor
  }
  const SensorModel sensor = make_sensor(preset.sensor, columns);
  Layout layout = build_layout(preset.layout, seed);
  const Scenario scenario = plan_scenario(std::move(layout), preset.changes, preset.route, seed);

  WriteOptions options;
  options.out = out;
  options.seed = seed;
  options.threads = threads;
  options.overwrite = overwrite;
  options.progress = isatty(STDERR_FILENO);
  options.body = body;
  options.skew = skew;
  if (format == "bag") options.bag = BagFormat::ros1;
  if (format == "ros2") options.bag = BagFormat::ros2_sqlite3;
  if (format == "mcap") options.bag = BagFormat::ros2_mcap;
  for (const std::string& e : effects) {
    if (e == "mixed-pixels" || e == "all") options.mixed_pixels = true;
    if (e == "dark-dropouts" || e == "all") options.dark_dropouts = true;
  }
  const WriteStats stats = write_dataset(scenario, sensor, options);

  size_t total = 0;
  for (size_t i = 0; i < stats.points_per_mission.size(); ++i) {
    std::printf("mission %s: %zu scans, %zu points\n", scenario.missions[i].name.c_str(), stats.scans_per_mission[i],
                stats.points_per_mission[i]);
    total += stats.points_per_mission[i];
  }
  std::map<std::string, int> kinds;
  for (const auto& [id, changes] : scenario.change_kind)
    for (const auto& kind : changes) ++kinds[kind];
  std::printf("changes:");
  for (const auto& [kind, n] : kinds) std::printf(" %s %d,", kind.c_str(), n);
  std::printf(" objects %zu\n", scenario.missions.front().objects.size());
  std::printf("preset %s (%s, %s): %zu points in %.2f s -> %s\n", preset.name.c_str(), preset.layout.kind.c_str(),
              sensor.name.c_str(), total, stats.seconds, out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lista-sim: simulated multi-mission LiDAR datasets with object-level change ground truth"};
  std::string preset, out, sensor;
  uint64_t seed = 1;
  int missions = 0, scans = 0, threads = default_threads();
  bool overwrite = false;
  app.add_option("--preset", preset, "tiny, demo, exp1, exp2, exp3, hall or fsc");
  app.add_option("--out", out, "dataset folder to write");
  app.add_option("--seed", seed, "random seed (same seed, same dataset)");
  app.add_option("--missions", missions, "number of missions, named A..Z (default: the preset's)")->check(CLI::Range(1, 26))->default_str("preset");
  app.add_option("--scans", scans, "scans per mission (default: the preset's)")->check(CLI::Range(1, 100000))->default_str("preset");
  app.add_option("--sensor", sensor,
                 "os0-128, xt32, vlp16, os1-64, hdl32, the non-repetitive mid360 or avia, or tls (a terrestrial "
                 "scanner: 360 x 300 deg at 0.2 deg, for stop-and-go stations with --scans 1) (default: the preset's)");
  app.add_option("--threads", threads, "worker threads")->check(lista::cli::at_least(1));
  app.add_flag("--overwrite", overwrite, "replace a dataset already in --out");
  bool body = false;
  app.add_flag("--body", body,
               "a legged robot's back in every scan: 1.1 x 0.5 m, 0.15-0.45 m under the sensor, moving with it "
               "(label 0; what filter.body finds)");
  std::vector<std::string> effects;
  app.add_option("--effects", effects,
                 "real sensor effects, comma-separated: mixed-pixels (returns between a depth edge's two surfaces, "
                 "where the beam's footprint, wider with range, straddles it), dark-dropouts (dark and grazing "
                 "returns fade with range), or all; default none, clean scans")
      ->delimiter(',')
      ->check(CLI::IsMember({"mixed-pixels", "dark-dropouts", "all"}));
  double drift = 1.0;
  app.add_option("--drift", drift,
                 "odometry drift, times the presets' (0.2 % of distance and 0.01 deg/m of heading, biased; "
                 "a legged robot's is several times that)")
      ->check(CLI::Range(0.0, 100.0));
  double map_tilt = 0.0;
  app.add_option("--map-tilt", map_tilt,
                 "each mission's map frame tilted by this many degrees in a random direction (a SLAM run started "
                 "on a slope, a handheld scanner); 0 = level, as the presets")
      ->check(CLI::Range(0.0, 45.0));
  int people = -1;
  app.add_option("--people", people,
                 "people walking through each mission, back and forth along the route, labelled as no object "
                 "(default: the preset's, 1 to 3)")
      ->check(CLI::Range(0, 50))
      ->default_str("preset");
  bool station_operator = false;
  app.add_flag("--operator", station_operator,
               "a person standing 1.5-2.5 m behind the sensor at each scan, facing it, somewhere else every scan "
               "(the surveyor beside a tripod scanner; labelled as no object, dynamic in ground_truth.json)");
  bool skew = false;
  app.add_flag("--skew", skew,
               "sweeps take 0.1 s while the sensor moves on: each ray is cast from where the sensor is at its time, "
               "so a moving sensor's scans come out skewed as real spinning LiDARs' do (bags also carry each "
               "point's time, field 'time', for deskewing)");
  double spin = 0.0;
  app.add_option("--spin", spin, "the sensor also turns about its up axis at this rate, deg/s (a robot turning on the spot)")
      ->check(CLI::Range(-720.0, 720.0));
  std::string format = "pcd";
  app.add_option("--format", format,
                 "how missions are written: pcd (the data contract's folders), bag (a ROS 1 .bag per mission), ros2 "
                 "(a ROS 2 bag, .db3) or mcap (a ROS 2 bag, .mcap); bags carry the clouds on /points, the poses on "
                 "/tf and /odom, and trajectory.txt beside them (docs/formats.md)")
      ->check(CLI::IsMember({"pcd", "bag", "ros2", "mcap"}))
      ->capture_default_str();
  std::string scene_furniture;
  app.add_option("--furniture", scene_furniture,
                 "also place Sweet Home 3D furniture from this folder, about a third of the objects "
                 "(tools/fetch-shapes.sh DIR unpacks it)");

  lista::sim::ViewsOptions views;
  auto* views_cmd = app.add_subcommand("views", "partial scans of single objects (descriptor training)");
  views_cmd->add_option("--out", views.out, "folder to write")->required();
  views_cmd->add_option("--objects", views.objects, "object instances")->check(lista::cli::at_least(1));
  views_cmd->add_option("--views-per-object", views.views_per_object, "views of each instance")
      ->check(lista::cli::at_least(1));
  views_cmd->add_option("--scans-per-view", views.scans_per_view,
                        "sweeps merged into each view, 1 m apart along a pass by the object (as a mission map sees it)")
      ->check(lista::cli::at_least(1));
  views_cmd->add_option("--sensors", views.sensors,
                        "sensors each view draws from (default os0-128,xt32,vlp16; also os1-64, hdl32, mid360, avia)")
      ->delimiter(',');
  views_cmd->add_option("--seed", views.seed, "random seed");
  views.threads = default_threads();
  views_cmd->add_option("--threads", views.threads, "worker threads")->check(lista::cli::at_least(1));
  views_cmd->add_flag("--overwrite", views.overwrite, "replace views already in --out");
  views_cmd
      ->add_option("--look-alike-tolerance", views.look_alike_tolerance,
                   "shapes whose surfaces lie within this many metres of each other share one id (0: only identical "
                   "meshes do)")
      ->check(CLI::Range(0.0f, 1.0f));
  std::string furniture;
  views_cmd->add_option("--furniture", furniture,
                        "also draw Sweet Home 3D furniture from this folder (tools/fetch-shapes.sh DIR unpacks it)");
  bool no_procedural = false;
  views_cmd->add_flag("--no-procedural", no_procedural, "draw only the --furniture shapes");
  app.require_subcommand(0, 1);
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-sim")) return *code;

  try {
    if (views_cmd->parsed()) {
      views.progress = isatty(STDERR_FILENO);
      views.procedural = !no_procedural;
      if (!furniture.empty()) views.extra_shapes = furniture_from(furniture, "lista-sim views");
      const auto stats = lista::sim::write_views(views);
      std::printf("views: %zu views of %d objects (%zu shapes), %zu points -> %s\n", stats.views, views.objects,
                  stats.shapes, stats.points, views.out.c_str());
      return 0;
    }
    if (preset.empty() || out.empty()) {
      std::cerr << "lista-sim: --preset and --out are required (or use the 'views' subcommand); see --help\n";
      return 2;
    }
    return run_dataset(preset, out, seed, missions, scans, sensor, threads, overwrite, scene_furniture, body, effects, drift, map_tilt, people, station_operator, format, skew, spin);
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
}
