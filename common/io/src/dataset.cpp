// Reading missions and datasets (data contract, sect. 1): poses.txt + scans/,
// or the VIEWPOINT layout (map-frame .pcd scans carrying the sensor pose).
#include "text_util.hpp"

#include <lista/error.hpp>
#include <lista/parallel.hpp>
#include <lista/utf8.hpp>
#include <lista_io/dataset.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace fs = std::filesystem;

namespace lista::io {

namespace {

bool is_scan_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".pcd" || ext == ".ply" || ext == ".bin";
}

// Scan files of a folder by extension. `listing`: only regular files (is this
// a mission?); reading takes every entry so that a folder or a broken link
// named like a scan is an error naming it, not a silently shorter list.
std::vector<std::string> files_in(const fs::path& dir, bool pcd_only, bool listing = false) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    const bool regular = it->is_regular_file(type_ec);
    if (listing && !regular) continue;
    const fs::path& p = it->path();
    // Hidden files are not scans: macOS leaves "._000001.pcd" metadata beside copied files.
    if (p.filename().string().front() == '.') continue;
    if (!(pcd_only ? p.extension() == ".pcd" : is_scan_file(p))) continue;
    // A folder or a broken link named like a scan is named here, before a
    // count of scans against poses would blame the poses.
    if (!regular) {
      const fs::file_status st = fs::status(p, type_ec);  // follows links
      const char* what = st.type() == fs::file_type::directory      ? ": is a folder, not a scan file"
                         : st.type() == fs::file_type::fifo         ? ": is a pipe (FIFO), not a scan file"
                         : st.type() == fs::file_type::character ||
                                 st.type() == fs::file_type::block  ? ": is a device, not a scan file"
                         : st.type() == fs::file_type::socket       ? ": is a socket, not a scan file"
                         : fs::is_symlink(fs::symlink_status(p, type_ec))
                             ? ": is a link to nothing readable (a broken link or a loop of links)"
                             : ": is not a readable scan file";
      throw Error(p.string() + what);
    }
    out.push_back(p.string());
  }
  if (ec) throw Error(dir.string() + ": cannot list (" + ec.message() + ")");
  std::sort(out.begin(), out.end());  // by file name: same folder, so full path order = name order
  return out;
}

// Regular, not hidden, files of `dir` whose extension (any case) is one of
// `endings`, sorted.
std::vector<std::string> files_ending(const fs::path& dir, const std::vector<std::string>& endings) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (!it->is_regular_file(type_ec) || it->path().filename().string().front() == '.') continue;
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (std::find(endings.begin(), endings.end(), ext) != endings.end()) out.push_back(it->path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The ROS 2 bag `dir` is ("" when none): itself when it holds metadata.yaml,
// else its one storage file.
std::string ros2_bag_in(const fs::path& dir) {
  std::error_code ec;
  if (fs::is_regular_file(dir / "metadata.yaml", ec)) return dir.string();
  const std::vector<std::string> storage = files_ending(dir, {".db3", ".mcap"});
  if (storage.size() > 1)
    throw Error(dir.string() + ": " + std::to_string(storage.size()) + " ROS 2 storage files and no metadata.yaml; " +
                "keep the bag's metadata.yaml beside them, or one file per mission");
  return storage.empty() ? std::string() : storage[0];
}

bool is_mission_dir(const fs::path& dir) {
  if (is_bag_mission(dir.string())) return true;
  // Any poses.txt (a folder by mistake too): reading it then says what is wrong.
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir / "poses.txt", ec))) return true;
  return !files_in(dir, true, true).empty();  // VIEWPOINT layout
}

// std::filesystem throws filesystem_error with its own wording ("filesystem
// error: status: Too many levels of symbolic links [path]"); the readers
// say it as every other error: the path, then what is wrong.
template <class F>
auto with_plain_fs_errors(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const fs::filesystem_error& e) {
    throw Error(e.path1().string() + ": cannot be read (" + e.code().message() + ")");
  }
}

}  // namespace

BagRecording bag_recording(const std::string& mission_dir) {
  const fs::path dir(mission_dir);
  BagRecording r;
  r.ros1_files = files_ending(dir, {".bag"});
  r.ros2 = ros2_bag_in(dir);
  if (!r.ros1_files.empty() && !r.ros2.empty())
    throw Error(mission_dir + ": holds both ROS 1 .bag files and a ROS 2 bag; keep one recording per mission folder");
  if (!r.empty()) return r;
  // A ROS 2 bag folder as the mission's only subfolder (what `ros2 bag record` makes).
  std::error_code ec;
  std::vector<fs::path> folders;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_directory(type_ec) && it->path().filename() != "scans") folders.push_back(it->path());
  }
  if (folders.size() == 1 && fs::is_regular_file(folders[0] / "metadata.yaml", ec)) r.ros2 = folders[0].string();
  return r;
}

bool is_bag_mission(const std::string& mission_dir) { return !bag_recording(mission_dir).empty(); }

static std::vector<std::string> list_missions_unchecked(const std::string& dataset_dir) {
  const fs::path root(dataset_dir);
  if (!fs::is_directory(root)) throw Error(dataset_dir + ": dataset folder does not exist");
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_directory()) continue;
    if (is_mission_dir(it->path())) {
      names.push_back(it->path().filename().string());
    } else if (fs::is_directory(it->path() / "scans")) {
      // A mission without its poses would be left out silently otherwise.
      throw Error(it->path().string() + ": has scans/ but no poses.txt; add the poses (docs/formats.md), or move "
                                        "the folder out of the dataset to leave the mission out");
    }
  }
  if (ec) throw Error(dataset_dir + ": cannot list (" + ec.message() + ")");
  std::sort(names.begin(), names.end());
  if (names.empty()) {
    // A single mission folder given as the dataset.
    if (is_mission_dir(root)) return {"."};
    throw Error(dataset_dir + ": no missions (expected folders with poses.txt and scans/, or .pcd scans with VIEWPOINT)");
  }
  return names;
}

bool is_viewpoint_layout(const std::string& mission_dir) {
  return !fs::exists(fs::path(mission_dir) / "poses.txt");
}

std::vector<char> scans_to_read(const std::vector<Eigen::Isometry3d>& poses, double spacing, double turn_deg) {
  std::vector<char> keep(poses.size(), 1);
  if (spacing <= 0.0 || poses.size() < 3) return keep;
  const double turn = turn_deg * M_PI / 180.0;
  size_t last = 0;
  for (size_t i = 1; i + 1 < poses.size(); ++i) {
    const Eigen::Isometry3d d = poses[last].inverse() * poses[i];
    const double angle = Eigen::AngleAxisd(d.linear()).angle();
    keep[i] = d.translation().norm() >= spacing || angle >= turn;
    if (keep[i]) last = i;
  }
  return keep;
}

double median_step(const std::vector<Eigen::Isometry3d>& poses) {
  if (poses.size() < 2) return 0.0;
  std::vector<double> steps;
  steps.reserve(poses.size() - 1);
  for (size_t i = 1; i < poses.size(); ++i) steps.push_back((poses[i].translation() - poses[i - 1].translation()).norm());
  return geometry::median(steps);
}

bool is_dense_log(const std::vector<Eigen::Isometry3d>& poses) {
  return poses.size() >= kDenseLogScans && median_step(poses) < kDenseLogStep;
}

double spacing_for(const std::vector<Eigen::Isometry3d>& poses, const DatasetOptions& options) {
  if (options.scan_spacing > 0.0) return options.scan_spacing;
  if (options.dense_spacing > 0.0 && is_dense_log(poses)) return options.dense_spacing;
  return 0.0;
}

static Mission read_mission_unchecked(const std::string& mission_dir, const DatasetOptions& options) {
  const fs::path dir(mission_dir);
  if (!fs::is_directory(dir)) throw Error(mission_dir + ": mission folder does not exist");
  if (is_bag_mission(mission_dir)) {
    if (!options.read_bag_mission)
      throw Error(mission_dir + ": a mission recorded as ROS bags, which this program does not read; run lista-run on it");
    Mission m = options.read_bag_mission(mission_dir, options);
    m.dir = mission_dir;
    m.name = fs::weakly_canonical(dir).filename().string();
    return m;
  }
  Mission m;
  m.dir = mission_dir;
  m.name = fs::weakly_canonical(dir).filename().string();
  const bool viewpoint_layout = is_viewpoint_layout(mission_dir);
  std::vector<std::string> files;
  std::vector<PoseRecord> poses;
  if (viewpoint_layout) {
    files = files_in(dir, true);
    if (files.empty())
      throw Error(mission_dir + ": empty mission (no poses.txt, no .pcd scans)");
  } else {
    poses = read_poses((dir / "poses.txt").string());
    if (!fs::is_directory(dir / "scans")) throw Error(mission_dir + ": has poses.txt but no scans/ folder");
    files = files_in(dir / "scans", false);
    if (poses.empty() && files.empty()) throw Error(mission_dir + ": empty mission (no poses, no scans)");
    if (files.size() != poses.size())
      throw Error(mission_dir + ": " + std::to_string(files.size()) + " scan files in scans/ but " +
                  std::to_string(poses.size()) + " poses in poses.txt");
  }
  m.scans.resize(files.size());
  std::vector<size_t> skipped(files.size(), 0);
  const bool need_read = options.load_points || viewpoint_layout;
  // The VIEWPOINT layout's poses are in the files' headers: read those
  // first when the mission may be thinned, so unread scans cost no points.
  std::vector<char> keep(files.size(), 1);
  std::vector<Eigen::Isometry3d> header_poses;
  if (!viewpoint_layout) {
    std::vector<Eigen::Isometry3d> sensor_poses;
    for (const auto& r : poses) sensor_poses.push_back(r.pose);
    keep = scans_to_read(sensor_poses, spacing_for(sensor_poses, options), options.scan_turn_deg);
  } else if (options.scan_spacing > 0.0 || options.dense_spacing > 0.0) {
    header_poses.resize(files.size());
    parallel_for(files.size(), options.threads, [&](size_t i) {
      header_poses[i] = read_pcd_viewpoint(files[i]).value_or(Eigen::Isometry3d::Identity());
    });
    keep = scans_to_read(header_poses, spacing_for(header_poses, options), options.scan_turn_deg);
  }
  parallel_for(files.size(), options.threads, [&](size_t i) {
    Scan& s = m.scans[i];
    s.file = files[i];
    if (!viewpoint_layout) {
      s.timestamp = poses[i].timestamp;
      s.pose = poses[i].pose;
    } else {
      s.timestamp = double(i);
    }
    if (!need_read || !keep[i]) {
      if (!header_poses.empty()) s.pose = header_poses[i];
      s.points = std::make_shared<const PointSet>();
      return;
    }
    // The VIEWPOINT layout's points are in the map frame: read_scan brings
    // them into the sensor frame, in double (the map may be georeferenced).
    ScanFile f = read_scan(files[i], static_cast<uint32_t>(i), viewpoint_layout);
    if (viewpoint_layout) s.pose = f.viewpoint.value_or(Eigen::Isometry3d::Identity());
    s.points_in_file = f.points_in_file;
    skipped[i] = f.skipped_nonfinite;
    if (!options.load_points) f.points = PointSet();
    s.points = std::make_shared<const PointSet>(std::move(f.points));
  });
  for (size_t k : skipped) m.skipped_nonfinite += k;
  if (fs::is_regular_file(dir / "poses_gt.txt")) {
    const auto gt = read_poses((dir / "poses_gt.txt").string());
    if (gt.size() != m.scans.size())
      throw Error(mission_dir + "/poses_gt.txt: " + std::to_string(gt.size()) + " poses for " +
                  std::to_string(m.scans.size()) + " scans");
    for (const auto& r : gt) m.poses_gt.push_back(r.pose);
  }
  return m;
}

static MissionSet read_dataset_unchecked(const std::string& dataset_dir, const DatasetOptions& options) {
  MissionSet set;
  set.dataset = dataset_dir;
  std::vector<std::string> names = options.missions.empty() ? list_missions_unchecked(dataset_dir) : options.missions;
  for (const auto& name : names) {
    const fs::path dir = name == "." ? fs::path(dataset_dir) : fs::path(dataset_dir) / name;
    // Mission names key report.json (UTF-8 JSON) and lista-eval's matching
    // of folders: a name in another encoding cannot round-trip.
    if (utf8_error_at(name) != std::string_view::npos)
      throw Error(dataset_dir + ": mission folder name '" + detail::escaped(name) +
                  "' is not UTF-8; rename it (report.json names missions in UTF-8)");
    if (!fs::is_directory(dir)) throw Error(dataset_dir + ": no mission '" + name + "'");
    for (const auto& seen : set.missions)
      if (seen.name == name) throw Error(dataset_dir + ": mission '" + name + "' listed twice");
    set.missions.push_back(read_mission_unchecked(dir.string(), options));
    if (name != ".") set.missions.back().name = name;
  }
  return set;
}

std::vector<std::string> list_missions(const std::string& dataset_dir) {
  return with_plain_fs_errors([&] { return list_missions_unchecked(dataset_dir); });
}

Mission read_mission(const std::string& mission_dir, const DatasetOptions& options) {
  return with_plain_fs_errors([&] { return read_mission_unchecked(mission_dir, options); });
}

MissionSet read_dataset(const std::string& dataset_dir, const DatasetOptions& options) {
  return with_plain_fs_errors([&] { return read_dataset_unchecked(dataset_dir, options); });
}

}  // namespace lista::io
