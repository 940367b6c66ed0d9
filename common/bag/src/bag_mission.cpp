// A bag mission: which topic and which poses (bag_mission.hpp), then two
// passes over the bag: cloud headers, tf and poses first (small), then the
// clouds to keep, converted one at a time so memory follows what is kept,
// not the bag's length.
#include "deskew.hpp"
#include "mission_file.hpp"
#include "tf_tree.hpp"
#include "trajectory.hpp"

#include <lista/error.hpp>
#include <lista_bag/bag_mission.hpp>
#include <lista_bag/cloud_points.hpp>
#include <lista_bag/ros1.hpp>
#include <lista_bag/ros2.hpp>
#include <lista_io/poses.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

namespace fs = std::filesystem;

namespace lista::bag {

namespace {

std::unique_ptr<Reader> open_mission_bags(const fs::path& dir) {
  const io::BagRecording r = io::bag_recording(dir.string());
  if (!r.ros1_files.empty()) return open_ros1(r.ros1_files);
  if (!r.ros2.empty()) return open_ros2(r.ros2);
  throw Error(dir.string() + ": no .bag file and no ROS 2 bag");
}

std::string topic_list(const std::vector<TopicInfo>& topics) {
  std::string s;
  for (const auto& t : topics) s += (s.empty() ? "" : ", ") + t.name + " (" + t.type + ")";
  return s.empty() ? "none" : s;
}

std::vector<const TopicInfo*> of_kind(const std::vector<TopicInfo>& topics, std::initializer_list<MessageKind> kinds) {
  std::vector<const TopicInfo*> out;
  for (const auto& t : topics)
    if (std::find(kinds.begin(), kinds.end(), t.kind) != kinds.end()) out.push_back(&t);
  return out;
}

const TopicInfo& cloud_topic(const std::vector<TopicInfo>& topics, const std::string& wanted, const std::string& bag) {
  if (!wanted.empty()) {
    for (const auto& t : topics)
      if (t.name == wanted) {
        if (t.kind != MessageKind::point_cloud)
          throw Error(bag + ": cloud_topic " + wanted + " is a " + t.type + ", not a sensor_msgs/PointCloud2");
        return t;
      }
    throw Error(bag + ": no topic " + wanted + " (cloud_topic); the bag has " + topic_list(topics));
  }
  const auto clouds = of_kind(topics, {MessageKind::point_cloud});
  if (clouds.size() == 1) return *clouds[0];
  if (clouds.empty()) throw Error(bag + ": no sensor_msgs/PointCloud2 topic; the bag has " + topic_list(topics));
  std::string names;
  for (const auto* t : clouds) names += (names.empty() ? "" : ", ") + t->name;
  throw Error(bag + ": " + std::to_string(clouds.size()) + " point cloud topics (" + names +
              "); name one as cloud_topic in mission.toml or --set <io stage>.cloud_topic=...");
}

struct CloudHeader {
  double stamp;
  std::string frame;
  uint64_t points;
};

// What the first pass gathers.
struct FirstPass {
  std::vector<CloudHeader> clouds;
  TfTree tf;
  bool has_tf = false;
  std::map<std::string, std::vector<StampedPose>> pose_topics;
};

FirstPass first_pass(Reader& reader, const std::vector<TopicInfo>& topics, const std::string& cloud) {
  FirstPass p;
  std::vector<std::string> wanted = {cloud};
  for (const auto* t : of_kind(topics, {MessageKind::tf, MessageKind::tf_static, MessageKind::odometry, MessageKind::pose_stamped}))
    wanted.push_back(t->name);
  Visitor v;
  v.cloud = [&](const std::string&, Cloud&& c) { p.clouds.push_back({c.stamp, c.frame_id, uint64_t(c.width) * c.height}); };
  v.tf = [&](const std::string&, std::vector<FrameTransform>&& t, bool is_static) {
    p.tf.add(t, is_static);
    p.has_tf = true;
  };
  v.pose = [&](const std::string& topic, StampedPose&& pose) { p.pose_topics[topic].push_back(std::move(pose)); };
  reader.read(wanted, v, true);
  p.tf.finish();
  return p;
}

// The sensor pose of each cloud in the mission's map frame (nullopt: outside
// the poses' time range), and how they were found.
struct Placement {
  std::vector<std::optional<Eigen::Isometry3d>> poses;
  std::string source;
  // The pose of a cloud frame at any time (deskew), and the median time
  // between the pose samples it interpolates.
  std::function<std::optional<Eigen::Isometry3d>(const std::string& frame, double stamp)> pose_at;
  double pose_interval = 0.0;
};

Placement place_by_tf(const FirstPass& p, const std::string& fixed_frame, const std::string& bag) {
  Placement out;
  const std::string sensor = p.clouds.front().frame;
  const std::string fixed = fixed_frame.empty() ? p.tf.root_of(sensor) : fixed_frame;
  if (!p.tf.knows(fixed)) throw Error(bag + ": fixed_frame '" + fixed + "' is not in /tf");
  for (const auto& c : p.clouds) {
    if (!p.tf.knows(c.frame)) throw Error(bag + ": the cloud's frame '" + c.frame + "' is not in /tf");
    out.poses.push_back(p.tf.lookup(fixed, c.frame, c.stamp));
  }
  out.source = "tf (" + fixed + " -> " + sensor + ")";
  out.pose_at = [&tf = p.tf, fixed](const std::string& frame, double t) { return tf.lookup(fixed, frame, t); };
  out.pose_interval = p.tf.median_interval(sensor);
  return out;
}

Placement place_by_trajectory(const FirstPass& p, std::shared_ptr<const Trajectory> trajectory, const std::string& body,
                              const std::string& source, BagMissionLog& log) {
  const Trajectory& body_poses = *trajectory;
  Placement out;
  out.source = source;
  out.pose_interval = body_poses.median_interval();
  auto mount = std::make_shared<std::map<std::string, Eigen::Isometry3d>>();  // T_body_sensor per cloud frame
  for (const auto& c : p.clouds) {
    auto it = mount->find(c.frame);
    if (it == mount->end()) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      if (!body.empty() && body != c.frame) {
        if (p.tf.knows(body) && p.tf.knows(c.frame) && p.tf.root_of(body) == p.tf.root_of(c.frame)) {
          // A sensor's mount is static (/tf_static): one lookup per frame.
          T = p.tf.lookup(body, c.frame, c.stamp).value_or(Eigen::Isometry3d::Identity());
        } else {
          log.notes.push_back("no tf from '" + body + "' to the cloud's frame '" + c.frame + "': the sensor is taken at the " +
                              "pose of '" + body + "' (set body_frame, or record /tf_static)");
        }
      }
      it = mount->emplace(c.frame, T).first;
    }
    const auto at = body_poses.at(c.stamp);
    out.poses.push_back(at ? std::optional<Eigen::Isometry3d>(*at * it->second) : std::nullopt);
  }
  out.pose_at = [trajectory, mount](const std::string& frame, double t) -> std::optional<Eigen::Isometry3d> {
    const auto at = trajectory->at(t);
    const auto m = mount->find(frame);
    if (!at || m == mount->end()) return std::nullopt;
    return *at * m->second;
  };
  return out;
}

Placement place(const FirstPass& p, const BagOptions& o, const fs::path& dir, const std::vector<TopicInfo>& topics,
                const std::string& bag, BagMissionLog& log) {
  const std::string sensor = p.clouds.front().frame;
  std::string source = o.poses;
  if (source.empty()) {
    if (p.has_tf && p.tf.knows(sensor) && p.tf.moves_under_root(sensor)) {
      source = "tf";
    } else {
      const auto streams = of_kind(topics, {MessageKind::odometry, MessageKind::pose_stamped});
      if (streams.size() != 1) {
        std::string names;
        for (const auto* t : streams) names += (names.empty() ? "" : ", ") + t->name;
        throw Error(bag + ": no poses for the clouds: their frame '" + sensor + "' " +
                    (p.tf.knows(sensor) ? "hangs under no moving /tf frame" : "is not in /tf") + " and the bag has " +
                    (streams.empty() ? std::string("no odometry or pose topic") : std::to_string(streams.size()) + " (" + names + ")") +
                    "; set poses in mission.toml to tf, a topic or a TUM file (docs/formats.md)");
      }
      source = streams[0]->name;
    }
  }
  if (source == "tf") {
    if (!p.has_tf) throw Error(bag + ": poses = tf, but the bag has no /tf");
    return place_by_tf(p, o.fixed_frame, bag);
  }
  if (p.pose_topics.count(source) || std::any_of(topics.begin(), topics.end(), [&](const TopicInfo& t) { return t.name == source; })) {
    const auto it = std::find_if(topics.begin(), topics.end(), [&](const TopicInfo& t) { return t.name == source; });
    if (it->kind != MessageKind::odometry && it->kind != MessageKind::pose_stamped)
      throw Error(bag + ": poses topic " + source + " is a " + it->type + ", not nav_msgs/Odometry or geometry_msgs/PoseStamped");
    const auto found = p.pose_topics.find(source);
    std::vector<StampedPose> stream = found == p.pose_topics.end() ? std::vector<StampedPose>{} : found->second;
    if (stream.empty()) throw Error(bag + ": poses topic " + source + " has no messages");
    const std::string body = !o.body_frame.empty() ? o.body_frame : !stream.front().child_frame.empty() ? stream.front().child_frame : sensor;
    return place_by_trajectory(p, std::make_shared<const Trajectory>(std::move(stream)), body, source, log);
  }
  const fs::path file = fs::path(source).is_absolute() ? fs::path(source) : dir / source;
  if (!fs::is_regular_file(file))
    throw Error(bag + ": poses '" + source + "' is neither tf, a topic of the bag (" + topic_list(topics) + ") nor a file in " +
                dir.string());
  std::vector<StampedPose> stream;
  io::PoseFormat format;
  for (const auto& r : io::read_poses(file.string(), &format)) stream.push_back({r.timestamp, "", "", r.pose});
  if (format == io::PoseFormat::kitti)
    throw Error(file.string() + ": KITTI poses carry no timestamps to match the clouds' stamps; write the trajectory as TUM "
                "(timestamp tx ty tz qx qy qz qw)");
  const std::string body = o.body_frame.empty() ? sensor : o.body_frame;
  return place_by_trajectory(p, std::make_shared<const Trajectory>(std::move(stream)), body, file.filename().string(), log);
}

}  // namespace

Mission read_bag_mission(const std::string& mission_dir, const io::DatasetOptions& options, const BagOptions& defaults,
                         BagMissionLog* log_out) {
  const fs::path dir(mission_dir);
  const MissionFile file = read_mission_file((dir / "mission.toml").string(), defaults);
  const BagOptions& o = file.options;
  io::DatasetOptions opt = options;
  if (file.scan_spacing) opt.scan_spacing = *file.scan_spacing;

  BagMissionLog log;
  std::unique_ptr<Reader> reader = open_mission_bags(dir);
  const std::string bag = reader->path();
  log.bag = bag;
  const std::vector<TopicInfo> topics = reader->topics();
  const std::string topic = cloud_topic(topics, o.cloud_topic, bag).name;
  log.cloud_topic = topic;

  FirstPass p = first_pass(*reader, topics, topic);
  if (p.clouds.empty()) throw Error(bag + ": topic " + topic + " has no messages");
  log.clouds = p.clouds.size();
  for (const auto& c : p.clouds) log.cloud_points += c.points;
  const Placement placed = place(p, o, dir, topics, bag, log);
  log.pose_source = placed.source;

  // Scans: the clouds that have a pose, in the bag's order.
  std::vector<size_t> scan_of_cloud(p.clouds.size(), SIZE_MAX);
  Mission m;
  for (size_t k = 0; k < p.clouds.size(); ++k) {
    if (!placed.poses[k]) {
      ++log.outside_poses;
      continue;
    }
    scan_of_cloud[k] = m.scans.size();
    Scan s;
    s.file = bag + ":" + topic + "#" + std::to_string(k);
    s.timestamp = p.clouds[k].stamp;
    s.pose = *placed.poses[k];
    s.points = std::make_shared<const PointSet>();
    m.scans.push_back(std::move(s));
  }
  if (m.scans.empty())
    throw Error(bag + ": none of the " + std::to_string(p.clouds.size()) + " clouds on " + topic + " lies in the time range of its poses (" +
                placed.source + ")");
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& s : m.scans) poses.push_back(s.pose);
  const std::vector<char> keep = io::scans_to_read(poses, io::spacing_for(poses, opt), opt.scan_turn_deg);

  if (opt.load_points) {
    size_t k = 0;
    Visitor v;
    v.cloud = [&](const std::string&, Cloud&& c) {
      const size_t cloud = k++;
      const size_t i = cloud < scan_of_cloud.size() ? scan_of_cloud[cloud] : SIZE_MAX;
      if (i == SIZE_MAX || !keep[i]) return;
      std::vector<double> times;
      io::ScanFile f = cloud_points(c, uint32_t(i), m.scans[i].file, o.deskew ? &times : nullptr);
      if (!times.empty()) {
        ++log.timed;
        // Pose samples farther apart than two sweeps cannot tell the motion
        // within one: read such clouds as they are.
        const auto [lo, hi] = std::minmax_element(times.begin(), times.end());
        if (placed.pose_interval > 0.0 && placed.pose_interval <= 2.0 * (*hi - *lo) &&
            deskew(f.points, times, c.stamp, [&](double t) { return placed.pose_at(c.frame_id, t); }))
          ++log.deskewed;
      }
      m.scans[i].points_in_file = f.points_in_file;
      m.skipped_nonfinite += f.skipped_nonfinite;
      m.scans[i].points = std::make_shared<const PointSet>(std::move(f.points));
    };
    reader->read({topic}, v, false);
    if (log.timed > log.deskewed) {
      char text[240];
      std::snprintf(text, sizeof text, "%zu of %zu clouds with per-point times not deskewed: poses every %.3g s (%s), "
                    "too sparse for their sweeps, or not covering them", log.timed - log.deskewed, log.timed,
                    placed.pose_interval, placed.source.c_str());
      log.notes.push_back(text);
    }
  }
  if (fs::is_regular_file(dir / "poses_gt.txt")) {
    const auto gt = io::read_poses((dir / "poses_gt.txt").string());
    if (gt.size() == m.scans.size())
      for (const auto& r : gt) m.poses_gt.push_back(r.pose);
    else
      log.notes.push_back("poses_gt.txt has " + std::to_string(gt.size()) + " poses for " + std::to_string(m.scans.size()) +
                          " clouds with poses: not used");
  }
  if (log_out) *log_out = std::move(log);
  return m;
}

}  // namespace lista::bag
