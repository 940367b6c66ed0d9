// io.missions: reads a dataset of missions (data contract, sect. 1).
#include <lista/lista.hpp>
#include <lista/param_table.hpp>
#include <lista/parallel.hpp>
#include <lista_bag/bag_mission.hpp>
#include <lista_io/dataset.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace lista::io {

namespace {

// The origin of the run's local frame (MissionSet::origin): the first pose's
// position rounded to whole kilometres, zero when it lies within a km of zero.
Eigen::Vector3d local_origin(const MissionSet& set) {
  for (const auto& m : set.missions)
    if (!m.scans.empty()) {
      const Eigen::Vector3d t = m.scans.front().pose.translation();
      if (t.cwiseAbs().maxCoeff() < 1000.0) return Eigen::Vector3d::Zero();
      return (t / 1000.0).array().round().matrix() * 1000.0;
    }
  return Eigen::Vector3d::Zero();
}

// Natural order: runs of digits compare by value ("week2" before "week10",
// "scan_2" before "scan_10"), everything else by character.
bool natural_less(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      size_t ei = i, ej = j;
      while (ei < a.size() && digit(a[ei])) ++ei;
      while (ej < b.size() && digit(b[ej])) ++ej;
      // Compare values without overflow: strip leading zeros, then length, then digits.
      size_t zi = i, zj = j;
      while (zi + 1 < ei && a[zi] == '0') ++zi;
      while (zj + 1 < ej && b[zj] == '0') ++zj;
      if (ei - zi != ej - zj) return ei - zi < ej - zj;
      if (int c = a.compare(zi, ei - zi, b, zj, ej - zj); c != 0) return c < 0;
      i = ei, j = ej;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

// Scans whose pose lies far off the rest of its mission (a pose 10 000 km
// away: a corrupt line, a unit mix-up): more than 100 times the median
// distance of the mission's poses from their median, and over 1 km. "" if
// none; else the first few named, for a warning.
std::string far_off_poses(const Mission& m) {
  if (m.scans.size() < 3) return "";
  std::vector<double> c[3];
  for (const auto& s : m.scans)
    for (int k = 0; k < 3; ++k) c[k].push_back(s.pose.translation()[k]);
  const Eigen::Vector3d centre(geometry::median(c[0]), geometry::median(c[1]), geometry::median(c[2]));
  std::vector<double> d;
  for (const auto& s : m.scans) d.push_back((s.pose.translation() - centre).norm());
  std::vector<double> ordered = d;
  const double spread = geometry::median(ordered), limit = std::max(1000.0, 100.0 * spread);
  std::string named;
  size_t far = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    if (d[i] <= limit || ++far > 3) continue;
    char text[160];
    std::snprintf(text, sizeof text, "%sscan %zu (%s) %.3g m", named.empty() ? "" : ", ", i,
                  std::filesystem::path(m.scans[i].file).filename().c_str(), d[i]);
    named += text;
  }
  if (far == 0) return "";
  char text[200];
  std::snprintf(text, sizeof text, "mission '%s': %zu scan pose(s) lie far from the others (median %.3g m from their "
                "centre): ", m.name.c_str(), far, spread);
  return text + named + (far > 3 ? ", ..." : "") + "; a corrupt line of poses.txt? Such a scan is placed there";
}

// Names sorted by character whose numbers say otherwise ("scan_10" sorts
// before "scan_2", "week10" before "week2"): the first such pair as
// "<a> sorts before <b>", or "" when the two orders agree.
std::string misordered(const std::vector<std::string>& sorted_names) {
  for (size_t k = 1; k < sorted_names.size(); ++k)
    if (natural_less(sorted_names[k], sorted_names[k - 1]))
      return sorted_names[k - 1] + " sorts before " + sorted_names[k];
  return {};
}

std::string misordered_scan_names(const Mission& m) {
  std::vector<std::string> names;
  for (const auto& scan : m.scans) names.push_back(std::filesystem::path(scan.file).filename().string());
  return misordered(names);
}

// Keeps, of the points `keep` of `xyz` (in file order), the first of each
// set at exactly the same coordinates (open addressing on the bits; -0 and
// +0 are one place).
void keep_first_occurrences(const std::vector<Eigen::Vector3f>& xyz, std::vector<uint32_t>& keep) {
  size_t size = 16;
  while (size < 2 * keep.size()) size *= 2;
  std::vector<uint32_t> slots(size, UINT32_MAX);
  auto bits = [](float v) {
    uint32_t b;
    v += 0.0f;
    std::memcpy(&b, &v, sizeof b);
    return uint64_t(b);
  };
  size_t kept = 0;
  for (const uint32_t i : keep) {
    const Eigen::Vector3f& p = xyz[i];
    size_t h = size_t((bits(p.x()) * 0x9E3779B97F4A7C15ull ^ bits(p.y()) * 0xC2B2AE3D27D4EB4Full ^
                       bits(p.z()) * 0x165667B19E3779F9ull) >> 17) & (size - 1);
    while (slots[h] != UINT32_MAX && xyz[slots[h]] != p) h = (h + 1) & (size - 1);
    if (slots[h] != UINT32_MAX) continue;  // a repeat
    slots[h] = i;
    keep[kept++] = i;
  }
  keep.resize(kept);
}

struct DroppedPoints {
  size_t near = 0, zero = 0, repeated = 0;
};

// What the stage reads and how: the dataset, the thinning of dense logs, and
// (its base) where a bag mission's clouds and poses come from.
struct MissionsConfig : bag::BagOptions {
  std::string path;
  std::vector<std::string> missions;
  double min_range = 0.0;      // m
  double scan_spacing = 0.0;   // m
  double dense_spacing = 0.5;  // m
  double scan_turn = 30.0;     // deg
};

const ParamTable<MissionsConfig>& param_table();

class MissionsStage : public Stage {
 public:
  explicit MissionsStage(const Params& p) : c_(param_table().read(p)) {}

  Outputs run(const Inputs&, Context& ctx) override {
    const std::string dataset = c_.path.empty() ? ctx.run_info().dataset : c_.path;
    if (dataset.empty())
      throw Error("no dataset: set 'path' or give the run a dataset (lista-run --dataset DIR)");
    const std::vector<std::string> names = c_.missions.empty() ? list_missions(dataset) : c_.missions;
    if (names.size() < 2) ctx.warn(dataset + ": only one mission; change detection needs two or more");
    // Missions are compared in sorted-name order (data contract) unless
    // listed; week10 before week2 is rarely what was meant.
    if (const std::string pair = c_.missions.empty() ? misordered(names) : ""; !pair.empty())
      ctx.warn(dataset + ": mission " + pair + " by name, and missions are compared in name order: list them in " +
               "the order they were recorded (--set " + ctx.stage_id() + ".missions=[...]) or zero-pad the numbers");
    DatasetOptions opt;
    opt.threads = ctx.threads();
    opt.scan_spacing = c_.scan_spacing;
    opt.dense_spacing = c_.dense_spacing;
    opt.scan_turn_deg = c_.scan_turn;
    bag::BagMissionLog bag_log;
    opt.read_bag_mission = [&](const std::string& dir, const DatasetOptions& o) {
      return bag::read_bag_mission(dir, o, c_, &bag_log);
    };
    MissionSet set;
    set.dataset = dataset;
    ctx.progress().begin("reading missions", names.size());
    for (const auto& name : names) {
      ctx.throw_if_cancelled();
      DatasetOptions one = opt;
      one.missions = {name};
      bag_log = {};
      MissionSet part = read_dataset(dataset, one);
      if (!bag_log.bag.empty()) say_bag(part.missions[0].name, bag_log, ctx);
      for (const auto& seen : set.missions)
        if (seen.name == part.missions[0].name) throw Error("mission '" + name + "' listed twice in 'missions'");
      set.missions.push_back(std::move(part.missions[0]));
      ctx.progress().advance();
    }
    ctx.progress().end();
    std::vector<Scan*> scans_read;
    for (auto& m : set.missions)
      for (auto& scan : m.scans) scans_read.push_back(&scan);
    std::vector<DroppedPoints> per_scan(scans_read.size());
    parallel_for(scans_read.size(), ctx.threads(), [&](size_t i) { per_scan[i] = drop_unusable_points(*scans_read[i]); });
    DroppedPoints dropped;
    for (const DroppedPoints& d : per_scan) {
      dropped.near += d.near;
      dropped.zero += d.zero;
      dropped.repeated += d.repeated;
    }
    set.origin = local_origin(set);
    if (!set.origin.isZero()) {
      for (auto& m : set.missions) {
        for (auto& s : m.scans) s.pose.translation() -= set.origin;
        for (auto& g : m.poses_gt) g.translation() -= set.origin;
      }
      char text[160];
      std::snprintf(text, sizeof text, "poses lie far from zero: working around (%.0f, %.0f, %.0f) m, added back in the report",
                    set.origin.x(), set.origin.y(), set.origin.z());
      ctx.info(text);
    }
    size_t points = 0, skipped = 0, scans = 0, read = 0;
    for (const auto& m : set.missions) {
      if (const std::string far = far_off_poses(m); !far.empty()) ctx.warn(far);
      std::vector<Eigen::Isometry3d> poses;
      for (const auto& s : m.scans) poses.push_back(s.pose);
      const double spacing = spacing_for(poses, opt);
      const std::vector<char> kept = scans_to_read(poses, spacing, c_.scan_turn);
      const size_t m_read = size_t(std::count(kept.begin(), kept.end(), 1));
      read += m_read;
      // Map-frame .pcd scans carry their pose in VIEWPOINT; PCL writes an
      // identity there by default, so identity everywhere means no poses.
      if (m.scans.size() > 1 && is_viewpoint_layout(m.dir) &&
          std::all_of(m.scans.begin(), m.scans.end(), [](const Scan& s) { return s.pose.isApprox(Eigen::Isometry3d::Identity()); }))
        ctx.warn("mission '" + m.name + "': every scan's VIEWPOINT is the identity; if the scans are in the sensor "
                 "frame, give their poses in poses.txt and put them in scans/ (docs/formats.md)");
      // Nothing to align or compare; later stages would blame the poses.
      if (m.point_count() == 0)
        throw Error("mission '" + m.name + "': none of its " + std::to_string(m.scans.size()) + " scans has a finite " +
                    (c_.min_range > 0 ? "point farther than min_range from the sensor" : std::string("point off the sensor origin")) +
                    "; leave it out with --set " + ctx.stage_id() +
                    ".missions=[...] (listing at least two others: change needs two missions to compare)");
      std::vector<std::string> empty;
      for (size_t i = 0; i < m.scans.size(); ++i)
        if (kept[i] && m.scans[i].points && m.scans[i].points->empty())
          empty.push_back(std::filesystem::path(m.scans[i].file).filename().string());
      if (!empty.empty())
        ctx.warn("mission '" + m.name + "': " + std::to_string(empty.size()) + " scan" + (empty.size() > 1 ? "s" : "") +
                 " with no finite point off the sensor origin (" + empty.front() + (empty.size() > 1 ? ", ..." : "") + ")");
      if (const std::string pair = misordered_scan_names(m); !pair.empty())
        ctx.warn("mission '" + m.name + "': " + pair +
                 " by name, and scans take their poses in file-name order: zero-pad the numbers (scan_002.pcd)");
      if (c_.scan_spacing <= 0.0) say_if_dense(m, poses, spacing, ctx);
      const size_t n = m.point_count();
      ctx.info("mission '" + m.name + "': " + std::to_string(m.scans.size()) + " scans" +
               (m_read < m.scans.size()
                    ? " (" + std::to_string(m_read) + " read, " + (c_.scan_spacing > 0.0 ? "scan_spacing" : "dense_spacing") + ")"
                    : std::string()) +
               ", " + std::to_string(n) +
               " points" + (m.skipped_nonfinite ? ", " + std::to_string(m.skipped_nonfinite) + " non-finite skipped" : "") +
               (m.poses_gt.empty() ? "" : ", poses_gt.txt"));
      points += n;
      skipped += m.skipped_nonfinite;
      scans += m.scans.size();
    }
    ctx.record("missions", double(set.missions.size()));
    ctx.record("scans", double(scans));
    ctx.record("scans_read", double(read));
    ctx.record("points", double(points));
    ctx.record("skipped_nonfinite", double(skipped));
    ctx.record("dropped_near", double(dropped.near));
    ctx.record("dropped_zero", double(dropped.zero));
    ctx.record("dropped_repeated", double(dropped.repeated));
    if (dropped.near > 0)
      ctx.info(std::to_string(dropped.near) + " points nearer than min_range to their sensor dropped");
    if (dropped.zero > 0)
      ctx.info(std::to_string(dropped.zero) + " points at (0, 0, 0), the sensor origin, dropped: a driver's way of "
               "writing a missing return");
    if (dropped.repeated > 0)
      ctx.info(std::to_string(dropped.repeated) + " points dropped that repeat an earlier point of their scan to the "
               "bit (a sweep written twice)");
    return Outputs::of("missions", std::move(set));
  }

 private:
  // Drops the points nearer than min_range to their sensor (the robot's own
  // body, the operator carrying the scanner: they move with the sensor and
  // would leave a trail of change along every path); always those at
  // exactly the sensor origin (many drivers write a missing return as
  // (0, 0, 0) rather than NaN, and no LiDAR measures a range of 0); and a
  // point that repeats an earlier point of its scan to the bit (exporters
  // that list a sweep twice: a repeated return is no new evidence, and
  // counted twice it doubles the votes and point counts downstream). Kept
  // points keep their file index, so changes/ still names original points.
  DroppedPoints drop_unusable_points(Scan& scan) const {
    DroppedPoints dropped;
    if (!scan.points) return dropped;
    const float r2 = float(c_.min_range * c_.min_range);
    const PointSet& all = *scan.points;
    std::vector<uint32_t> keep;
    keep.reserve(all.size());
    for (size_t i = 0; i < all.size(); ++i) {
      const float d2 = all.xyz[i].squaredNorm();
      if (d2 == 0.0f)
        ++dropped.zero;
      else if (d2 < r2)
        ++dropped.near;
      else
        keep.push_back(uint32_t(i));
    }
    const size_t before = keep.size();
    keep_first_occurrences(all.xyz, keep);
    dropped.repeated = before - keep.size();
    if (keep.size() != all.size()) scan.points = std::make_shared<PointSet>(all.select(keep));
    return dropped;
  }

  // What a bag mission was read from, and what of it could not be used.
  void say_bag(const std::string& mission, const bag::BagMissionLog& log, Context& ctx) const {
    ctx.info("mission '" + mission + "': " + log.bag + ", " + std::to_string(log.clouds) + " clouds on " + log.cloud_topic +
             ", poses from " + log.pose_source);
    if (log.outside_poses > 0)
      ctx.warn("mission '" + mission + "': " + std::to_string(log.outside_poses) + " of " + std::to_string(log.clouds) +
               " clouds lie outside the time range of their poses (" + log.pose_source + ") and were skipped");
    if (log.deskewed > 0)
      ctx.info("mission '" + mission + "': " + std::to_string(log.deskewed) + " clouds deskewed by their per-point times");
    for (const auto& note : log.notes) ctx.warn("mission '" + mission + "': " + note);
  }

  // A log of many scans taken close together (a 10 Hz LiDAR) costs time and
  // memory in every later stage for little new evidence: said once per
  // mission, with what was read of it and the parameter that decides.
  void say_if_dense(const Mission& m, const std::vector<Eigen::Isometry3d>& poses, double spacing, Context& ctx) const {
    if (!is_dense_log(poses)) return;
    char text[360];
    if (spacing > 0.0)
      std::snprintf(text, sizeof text,
                    "mission '%s': a dense log (%zu scans, %.2f m apart at the median): reading a scan every %.2g m "
                    "or %.0f deg of turn (--set %s.dense_spacing=0 reads every scan)",
                    m.name.c_str(), m.scans.size(), median_step(poses), spacing, c_.scan_turn, ctx.stage_id().c_str());
    else
      std::snprintf(text, sizeof text,
                    "mission '%s': a dense log (%zu scans, %.2f m apart at the median), read whole (dense_spacing = 0)",
                    m.name.c_str(), m.scans.size(), median_step(poses));
    ctx.info(text);
  }

  MissionsConfig c_;
};

StageInfo info() {
  StageInfo s;
  s.name = "io.missions";
  s.version = "1.5.0";
  s.summary = "reads a dataset of missions (poses.txt + scans/, the VIEWPOINT layout, or ROS 1/ROS 2 bags)";
  s.doc =
      "Reads a dataset's missions (data contract, section 1): poses.txt and scans/ (PCD, PLY, KITTI .bin), the "
      "VIEWPOINT layout, or ROS 1 and ROS 2 bags; thins dense logs, drops non-finite, zero and repeated points, and moves "
      "georeferenced poses near zero. "
      "Details: docs/formats.md, \"Input: a dataset of missions\".";
  s.outputs = {{"missions", "missions", "the missions, each in its own map frame (to_common = identity)"}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<MissionsConfig>& param_table() {
  using C = MissionsConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("path", &C::path, "dataset folder; empty = the run's dataset (lista-run --dataset)");
    t.bind("missions", &C::missions, "mission folder names in the order to use; empty = all, sorted");
    t.bind("min_range", &C::min_range,
           "points nearer their sensor than this are dropped (a blunt way to drop the robot's body); 0 keeps all")
        .range(0, 100)
        .unit("m");
    t.bind("scan_spacing", &C::scan_spacing,
           "read a scan only where its sensor lies this far from the last scan read (or has turned scan_turn), in every mission; 0 = dense_spacing decides")
        .range(0, 100)
        .unit("m");
    t.bind("dense_spacing", &C::dense_spacing,
           "a dense log (500 or more scans under 0.1 m apart at the median) is read as with scan_spacing = this; 0 reads every scan")
        .range(0, 100)
        .unit("m");
    t.bind("cloud_topic", &C::cloud_topic, "bag missions: the sensor_msgs/PointCloud2 topic; empty = the only one");
    t.bind("poses", &C::poses,
           "bag missions: where the clouds' poses come from: tf, an odometry or pose topic, or a TUM file; empty = chosen from the bag");
    t.bind("fixed_frame", &C::fixed_frame,
           "bag missions with tf poses: the map frame; empty = the root of the cloud frame's tf tree");
    t.bind("body_frame", &C::body_frame,
           "bag missions with a pose topic or file: the frame they give poses of; empty = the odometry's child frame, "
           "else the cloud's frame (the sensor hangs under it through tf)");
    t.bind("deskew", &C::deskew,
           "bag missions: clouds with per-point times (Ouster t, Velodyne time, ...) are deskewed by the poses' "
           "motion during the sweep, when the poses are sampled at least every two sweeps");
    t.bind("scan_turn", &C::scan_turn,
           "when thinning (scan_spacing or dense_spacing), a scan turned this far from the last one read is read too")
        .range(0.1, 180)
        .unit("deg");
  });
}

}  // namespace

}  // namespace lista::io

LISTA_STAGE_PLUGIN(lista::io::info, lista::io::MissionsStage)
