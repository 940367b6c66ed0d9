// The rosbag2 layer over the storages: metadata.yaml, topics merged over a
// bag's files, CDR decoding into the plain messages, and the bag writer.
#include <lista_bag/ros2.hpp>

#include "cdr.hpp"
#include "metadata.hpp"
#include "storage.hpp"

#include <lista/error.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace lista::bag {
namespace {

using ros2::StorageReader;
using ros2::StorageTopic;

std::string extension_of(const std::string& path) { return fs::path(path).extension().string(); }

class Ros2Reader : public Reader {
 public:
  Ros2Reader(std::string path, std::vector<std::unique_ptr<StorageReader>> files) : path_(std::move(path)), files_(std::move(files)) {
    for (const auto& f : files_)
      for (const StorageTopic& t : f->topics()) {
        auto [it, fresh] = index_.emplace(t.name, merged_.size());
        if (fresh) merged_.push_back(t);
        else merged_[it->second].messages += t.messages;
      }
  }

  std::vector<TopicInfo> topics() const override {
    std::vector<TopicInfo> out;
    for (const StorageTopic& t : merged_) out.push_back({t.name, t.type, kind_of(t.name, t.type), t.messages});
    return out;
  }

  std::string path() const override { return path_; }

  void read(const std::vector<std::string>& topics, const Visitor& visitor, bool clouds_headers_only) override {
    std::set<std::string> wanted;
    for (const std::string& name : topics) {
      const auto it = index_.find(name);
      if (it == index_.end()) throw Error(path_ + ": no topic '" + name + "' in the bag");
      const StorageTopic& t = merged_[it->second];
      check_readable(t);
      const MessageKind kind = kind_of(t.name, t.type);
      const bool visited = kind == MessageKind::point_cloud ? bool(visitor.cloud)
                           : kind == MessageKind::tf || kind == MessageKind::tf_static ? bool(visitor.tf)
                                                                                        : bool(visitor.pose);
      if (visited) wanted.insert(name);
    }
    if (wanted.empty()) return;
    for (const auto& file : files_)
      file->read(wanted, [&](const StorageTopic& t, int64_t time_ns, const uint8_t* data, size_t size) {
        dispatch(*file, t, time_ns, data, size, visitor, clouds_headers_only);
      });
  }

 private:
  void check_readable(const StorageTopic& t) const {
    if (kind_of(t.name, t.type) == MessageKind::other)
      throw Error(path_ + ": topic '" + t.name + "' has type '" + t.type +
                  "', which LiSTA does not read (sensor_msgs/msg/PointCloud2, tf2_msgs/msg/TFMessage, nav_msgs/msg/Odometry, "
                  "geometry_msgs/msg/PoseStamped)");
    if (t.encoding != "cdr")
      throw Error(path_ + ": topic '" + t.name + "' is encoded as '" + t.encoding + "'; LiSTA reads only cdr");
  }

  // Decoding errors get the file, topic and receive time; the visitor's own
  // errors pass through untouched.
  void dispatch(const StorageReader& file, const StorageTopic& t, int64_t time_ns, const uint8_t* data, size_t size,
                const Visitor& visitor, bool headers_only) const {
    check_readable(t);  // a later file may disagree with the first on a topic's type
    const auto decode = [&](auto coder) {
      try {
        return coder();
      } catch (const Error& e) {
        throw Error(file.path() + ": topic '" + t.name + "', message received at " + std::to_string(time_ns) + " ns: " + e.message());
      }
    };
    switch (const MessageKind kind = kind_of(t.name, t.type)) {
      case MessageKind::point_cloud:
        return visitor.cloud(t.name, decode([&] { return cdr::decode_cloud(data, size, headers_only); }));
      case MessageKind::tf:
      case MessageKind::tf_static:
        return visitor.tf(t.name, decode([&] { return cdr::decode_tf(data, size); }), kind == MessageKind::tf_static);
      case MessageKind::odometry:
        return visitor.pose(t.name, decode([&] { return cdr::decode_odometry(data, size); }));
      default:
        return visitor.pose(t.name, decode([&] { return cdr::decode_pose_stamped(data, size); }));
    }
  }

  std::string path_;
  std::vector<std::unique_ptr<StorageReader>> files_;
  std::vector<StorageTopic> merged_;
  std::map<std::string, size_t> index_;
};

std::string read_text(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::unique_ptr<Reader> open_folder(const fs::path& folder) {
  const std::string meta = (folder / "metadata.yaml").string();
  if (!fs::is_regular_file(meta)) throw Error(folder.string() + ": no metadata.yaml, not a ROS 2 bag folder");
  const ros2::BagMetadata m = ros2::parse_metadata(read_text(meta), meta);
  std::vector<std::unique_ptr<StorageReader>> files;
  for (const std::string& rel : m.relative_file_paths) {
    fs::path file = folder / rel;
    // Foxy listed files with the bag folder's name in front.
    if (!fs::exists(file) && fs::exists(folder / fs::path(rel).filename())) file = folder / fs::path(rel).filename();
    if (!fs::is_regular_file(file)) throw Error(meta + ": storage file '" + rel + "' (relative_file_paths) does not exist");
    files.push_back(m.storage_identifier == "mcap" ? ros2::open_mcap(file.string()) : ros2::open_sqlite(file.string()));
  }
  return std::make_unique<Ros2Reader>(folder.string(), std::move(files));
}

int64_t to_ns(double seconds, const std::string& where) {
  if (!std::isfinite(seconds) || std::fabs(seconds) > 9.2e9) throw Error(where + ": record time " + std::to_string(seconds) + " s is out of range");
  return std::llround(seconds * 1e9);
}

class Ros2Writer : public Writer {
 public:
  Ros2Writer(fs::path folder, Ros2Storage storage) : folder_(std::move(folder)) {
    const std::string name = folder_.filename().string();
    if (storage == Ros2Storage::mcap) {
      storage_id_ = "mcap";
      file_ = name + "_0.mcap";
      out_ = ros2::create_mcap((folder_ / file_).string());
    } else {
      storage_id_ = "sqlite3";
      file_ = name + "_0.db3";
      out_ = ros2::create_sqlite((folder_ / file_).string());
    }
  }
  ~Ros2Writer() override {
    try {
      close();
    } catch (...) {  // the interface's promise: close() reports, the destructor cannot
    }
  }

  void write_cloud(const std::string& topic, const Cloud& cloud, double t) override {
    put(topic, "sensor_msgs/msg/PointCloud2", t, [&] { return cdr::encode_cloud(cloud); });
  }
  void write_tf(const std::string& topic, const std::vector<FrameTransform>& tf, double t) override {
    put(topic, "tf2_msgs/msg/TFMessage", t, [&] { return cdr::encode_tf(tf); });
  }
  void write_odometry(const std::string& topic, const StampedPose& pose, double t) override {
    put(topic, "nav_msgs/msg/Odometry", t, [&] { return cdr::encode_odometry(pose); });
  }
  void write_pose_stamped(const std::string& topic, const StampedPose& pose, double t) override {
    put(topic, "geometry_msgs/msg/PoseStamped", t, [&] { return cdr::encode_pose_stamped(pose); });
  }

  void close() override {
    if (closed_) return;
    closed_ = true;
    out_->close();
    ros2::write_file_atomically((folder_ / "metadata.yaml").string(),
                                ros2::format_metadata(storage_id_, file_, topics_, first_, last_));
  }

 private:
  template <class Encode>
  void put(const std::string& topic, const char* type, double record_time, Encode encode) {
    const std::string where = (folder_ / file_).string();
    if (closed_) throw Error(where + ": written after close");
    auto [it, fresh] = index_.emplace(topic, topics_.size());
    if (fresh) topics_.push_back({topic, type, 0});
    ros2::TopicCount& t = topics_[it->second];
    if (t.type != type) throw Error(where + ": topic '" + topic + "' already holds " + t.type + ", cannot write a " + type);
    const int64_t ns = to_ns(record_time, where);
    std::vector<uint8_t> bytes;
    try {
      bytes = encode();
    } catch (const Error& e) {
      throw Error(where + ": topic '" + topic + "': " + e.message());
    }
    out_->write(topic, type, ns, bytes);
    first_ = messages_ ? std::min(first_, ns) : ns;
    last_ = messages_ ? std::max(last_, ns) : ns;
    ++messages_;
    ++t.messages;
  }

  fs::path folder_;
  std::string storage_id_, file_;
  std::unique_ptr<ros2::StorageWriter> out_;
  std::vector<ros2::TopicCount> topics_;
  std::map<std::string, size_t> index_;
  int64_t first_ = 0, last_ = 0;
  uint64_t messages_ = 0;
  bool closed_ = false;
};

}  // namespace

namespace ros2 {
void write_file_atomically(const std::string& file, const std::string& text) {
  const std::string tmp = file + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
      std::remove(tmp.c_str());
      throw Error(file + ": cannot write " + tmp);
    }
  }
  if (std::rename(tmp.c_str(), file.c_str()) != 0) throw Error(file + ": cannot rename " + tmp + " to it");
}
}  // namespace ros2

std::unique_ptr<Reader> open_ros2(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return open_folder(path);
  if (!fs::is_regular_file(path, ec)) throw Error(path + ": no such file or folder");
  if (fs::path(path).filename() == "metadata.yaml") return open_folder(fs::path(path).parent_path());
  const std::string ext = extension_of(path);
  std::vector<std::unique_ptr<StorageReader>> files;
  if (ext == ".db3") files.push_back(ros2::open_sqlite(path));
  else if (ext == ".mcap") files.push_back(ros2::open_mcap(path));
  else throw Error(path + ": not a ROS 2 bag (a folder with metadata.yaml, or a .db3 or .mcap file)");
  return std::make_unique<Ros2Reader>(path, std::move(files));
}

std::unique_ptr<Writer> create_ros2(const std::string& folder, Ros2Storage storage) {
  fs::path dir = fs::path(folder).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();  // "bag/" -> "bag"
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec) || !fs::is_empty(dir, ec))
      throw Error(folder + ": exists and is not an empty folder; a new bag needs a fresh one");
  } else if (!fs::create_directories(dir, ec)) {
    throw Error(folder + ": cannot create the bag folder: " + ec.message());
  }
  return std::make_unique<Ros2Writer>(dir, storage);
}

}  // namespace lista::bag
