// ROS 1 bags through rosbag_storage: the message classes of sensor_msgs,
// tf2_msgs, nav_msgs and geometry_msgs decode and encode; this file only
// converts them to and from the plain structs of messages.hpp.
#include <lista/error.hpp>
#include <lista_bag/ros1.hpp>

#include <bzlib.h>
#include <console_bridge/console.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <roslz4/lz4s.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>

namespace lista::bag {

namespace {

Eigen::Isometry3d to_isometry(const geometry_msgs::Point& t, const geometry_msgs::Quaternion& q, const std::string& where) {
  const auto T = rigid_transform(Eigen::Vector3d(t.x, t.y, t.z), q.x, q.y, q.z, q.w);
  if (!T) throw Error(where + ": a pose whose rotation quaternion is zero or whose numbers are not finite");
  return *T;
}

geometry_msgs::Point to_point(const Eigen::Vector3d& t) {
  geometry_msgs::Point p;
  p.x = t.x(), p.y = t.y(), p.z = t.z();
  return p;
}

geometry_msgs::Quaternion to_quaternion(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  geometry_msgs::Quaternion out;
  out.x = q.x(), out.y = q.y(), out.z = q.z(), out.w = q.w();
  return out;
}

double seconds(const ros::Time& t) { return t.toSec(); }

ros::Time ros_time(double s, const std::string& what) {
  if (!(s >= 0.0 && s < 4294967295.0)) throw Error(what + ": a time ROS 1 cannot store (" + std::to_string(s) + " s)");
  return ros::Time(s);
}

Cloud from_ros(const sensor_msgs::PointCloud2& m, bool headers_only) {
  Cloud c;
  c.stamp = seconds(m.header.stamp);
  c.frame_id = m.header.frame_id;
  c.height = m.height, c.width = m.width, c.point_step = m.point_step, c.row_step = m.row_step;
  c.is_bigendian = m.is_bigendian, c.is_dense = m.is_dense;
  for (const auto& f : m.fields) c.fields.push_back({f.name, f.offset, f.datatype, f.count});
  if (!headers_only) c.data = m.data;
  return c;
}

// rosbag trusts every length a file states (a record header of 2 GB is
// allocated before it is found missing): the record structure is walked
// first, its lengths checked against the file, and a chunk's stated
// uncompressed size against what compression can give. A compressed chunk
// is decompressed and its records walked too: rosbag parses their headers
// without checking them against the chunk.
class RecordWalk {
 public:
  explicit RecordWalk(const std::string& file) : file_(file), in_(file, std::ios::binary) {
    if (!in_) throw Error(file + ": cannot be read");
    in_.seekg(0, std::ios::end);
    size_ = uint64_t(in_.tellg());
  }

  void check() {
    static const char magic[] = "#ROSBAG V2.0\n";
    if (size_ < 13 || bytes(0, 13) != magic)
      throw Error(file_ + ": not a ROS 1 bag (version 2.0); a ROS 2 bag is a folder with metadata.yaml");
    for (uint64_t at = 13; at < size_;) {
      starts_.insert(at);
      at = record(at, size_, true);
    }
    // rosbag jumps to the index the bag header names, and to each chunk a
    // chunk info names: both must be where a record begins.
    if (index_pos_ != 0 && !starts_.count(index_pos_))
      throw Error(file_ + ": the bag header's index position " + std::to_string(index_pos_) +
                  " is not a record's start: a corrupt bag; try `rosbag reindex` on a copy");
    for (uint64_t chunk : chunk_positions_)
      if (!starts_.count(chunk))
        throw Error(file_ + ": a chunk info names byte " + std::to_string(chunk) + ", not a record's start: a corrupt bag");
  }

 private:
  // Bytes [at, at + n) of the file, or of the decompressed chunk being walked.
  std::string bytes(uint64_t at, uint64_t n) {
    std::string out(size_t(n), '\0');
    if (chunk_) {
      if (at + n > chunk_->size()) throw truncated(at);
      std::memcpy(out.data(), chunk_->data() + at, size_t(n));
      return out;
    }
    in_.seekg(std::streamoff(at));
    in_.read(out.data(), std::streamsize(n));
    if (!in_) throw truncated(at);
    return out;
  }
  uint32_t u32(uint64_t at) {
    const std::string b = bytes(at, 4);
    return uint32_t(uint8_t(b[0])) | uint32_t(uint8_t(b[1])) << 8 | uint32_t(uint8_t(b[2])) << 16 |
           uint32_t(uint8_t(b[3])) << 24;
  }
  Error truncated(uint64_t at) const {
    if (chunk_)
      return Error(file_ + ": a record at byte " + std::to_string(at) + " of the compressed chunk at byte " +
                   std::to_string(chunk_at_) + " runs past the chunk's end: a corrupt bag");
    return Error(file_ + ": a record at byte " + std::to_string(at) + " runs past the end of the file (" +
                 std::to_string(size_) + " bytes): a truncated or corrupt bag; try `rosbag reindex` on a copy");
  }
  // The chunk's data decompressed to its stated size.
  std::vector<char> decompressed(uint64_t at, uint64_t data_at, uint64_t data_len, uint64_t size,
                                 const std::string& compression) {
    std::string packed = bytes(data_at, data_len);
    std::vector<char> out(size_t(size) + 1);  // one spare byte: a chunk that holds more than it states fails
    unsigned int got = unsigned(out.size());
    const bool ok = compression == "lz4"
                        ? roslz4_buffToBuffDecompress(packed.data(), unsigned(packed.size()), out.data(), &got) ==
                              ROSLZ4_OK
                        : BZ2_bzBuffToBuffDecompress(out.data(), &got, packed.data(), unsigned(packed.size()), 0, 0) ==
                              BZ_OK;
    if (!ok || got != size)
      throw Error(file_ + ": the " + compression + " chunk at byte " + std::to_string(at) + " does not decompress to the " +
                  std::to_string(size) + " bytes it states: a corrupt bag");
    out.resize(size_t(size));
    return out;
  }
  // Walks the record at `at` (within [at, end)); returns where the next
  // begins. `top`: a record of the file, not one inside a chunk.
  uint64_t record(uint64_t at, uint64_t end, bool top) {
    if (at + 4 > end) throw truncated(at);
    const uint64_t header_len = u32(at);
    if (at + 4 + header_len + 4 > end) throw truncated(at);
    uint8_t op = 0;
    uint64_t chunk_size = 0, position = 0, count = 0;
    std::string compression;
    for (uint64_t f = at + 4; f < at + 4 + header_len;) {
      const uint64_t field_len = u32(f);
      if (f + 4 + field_len > at + 4 + header_len) throw truncated(f);
      const std::string field = bytes(f + 4, field_len);
      const size_t eq = field.find('=');
      const std::string name = field.substr(0, eq), value = eq == std::string::npos ? "" : field.substr(eq + 1);
      if (name == "op" && value.size() == 1) op = uint8_t(value[0]);
      if (name == "size" && value.size() == 4) {
        chunk_size = 0;
        for (int k = 3; k >= 0; --k) chunk_size = chunk_size << 8 | uint8_t(value[size_t(k)]);
      }
      if (name == "compression") compression = value;
      if (name == "count" && value.size() == 4)
        for (int k = 3; k >= 0; --k) count = count << 8 | uint8_t(value[size_t(k)]);
      if ((name == "index_pos" || name == "chunk_pos") && value.size() == 8)
        for (int k = 7; k >= 0; --k) position = position << 8 | uint8_t(value[size_t(k)]);
      f += 4 + field_len;
    }
    if (op == 0x03 && top) index_pos_ = position;  // the bag header
    if (op == 0x06 && top) chunk_positions_.push_back(position);  // a chunk info
    const uint64_t data_at = at + 4 + header_len + 4, data_len = u32(at + 4 + header_len);
    if (data_at + data_len > end) throw truncated(at);
    if (op == 0x07)  // a connection: its data is a header of fields too
      for (uint64_t f = data_at; f < data_at + data_len;) {
        const uint64_t field_len = u32(f);
        if (f + 4 + field_len > data_at + data_len) throw truncated(f);
        f += 4 + field_len;
      }
    if (op == 0x05 && top) {  // a chunk
      if (compression == "none" && chunk_size != data_len)
        throw Error(file_ + ": the chunk at byte " + std::to_string(at) + " states " + std::to_string(chunk_size) +
                    " bytes but holds " + std::to_string(data_len) + ": a corrupt bag");
      if (chunk_size > (uint64_t(1) << 30) || chunk_size > 1000 * data_len + (1 << 20))
        throw Error(file_ + ": the chunk at byte " + std::to_string(at) + " states " + std::to_string(chunk_size) +
                    " bytes uncompressed from " + std::to_string(data_len) + ": a corrupt bag");
      chunk_size_ = chunk_size;
      chunk_starts_.clear();
      if (compression == "none") {
        for (uint64_t inner = data_at; inner < data_at + data_len;) {
          chunk_starts_.insert(inner - data_at);
          inner = record(inner, data_at + data_len, false);
        }
      } else if (compression == "lz4" || compression == "bz2") {
        const std::vector<char> plain = decompressed(at, data_at, data_len, chunk_size, compression);
        chunk_ = &plain;
        chunk_at_ = at;
        try {
          for (uint64_t inner = 0; inner < plain.size();) {
            chunk_starts_.insert(inner);
            inner = record(inner, plain.size(), false);
          }
        } catch (...) {
          chunk_ = nullptr;
          throw;
        }
        chunk_ = nullptr;
      } else {
        throw Error(file_ + ": the chunk at byte " + std::to_string(at) + " is compressed with '" + compression +
                    "', which ROS 1 bags do not use (none, lz4 or bz2): a corrupt bag");
      }
    }
    if (op == 0x04 && top) {  // a chunk's index: (time, offset) of each message in it
      if (data_len != 12 * count) throw Error(file_ + ": the index at byte " + std::to_string(at) + " is corrupt");
      for (uint64_t e = 0; e < count; ++e) {
        const uint64_t offset = u32(data_at + 12 * e + 8);
        if (offset + 8 > chunk_size_ || !chunk_starts_.count(offset))
          throw Error(file_ + ": the index at byte " + std::to_string(at) + " points outside its chunk's records: a corrupt bag");
      }
    }
    return data_at + data_len;
  }

  std::string file_;
  std::ifstream in_;
  uint64_t size_ = 0, index_pos_ = 0;
  std::set<uint64_t> starts_;              // where top-level records begin
  uint64_t chunk_size_ = 0;                // the last chunk's uncompressed size and
  std::set<uint64_t> chunk_starts_;        // where its records begin (offsets in it)
  std::vector<uint64_t> chunk_positions_;  // named by chunk infos
  const std::vector<char>* chunk_ = nullptr;  // the decompressed chunk being walked, if any
  uint64_t chunk_at_ = 0;
};

// ros::serialization sizes a vector by the count it reads before reading
// its elements: a corrupt count allocates gigabytes. The two message types
// with variable-size arrays have their counts checked against the bytes the
// message holds first (an element takes at least `smallest` bytes).
class CountCheck {
 public:
  CountCheck(const rosbag::MessageInstance& m, const std::string& where) : where_(where), bytes_(m.size()) {
    ros::serialization::OStream out(bytes_.data(), uint32_t(bytes_.size()));
    m.write(out);
  }
  void tf_message() {
    at_ = 0;
    count(4 + 8 + 4 + 4 + 56);  // TransformStamped: header, child frame, transform
  }
  void point_cloud() {
    at_ = 0;
    skip(4 + 8), text();  // header: seq, stamp, frame_id
    skip(8);              // height, width
    const uint32_t fields = count(4 + 4 + 1 + 4);
    for (uint32_t k = 0; k < fields; ++k) text(), skip(9);
    skip(1 + 4 + 4);  // is_bigendian, point_step, row_step
    count(1);         // data
  }

 private:
  uint32_t u32() {
    if (at_ + 4 > bytes_.size()) throw Error(where_ + ": a message shorter than its fields (a corrupt bag)");
    uint32_t v = 0;
    std::memcpy(&v, bytes_.data() + at_, 4);
    at_ += 4;
    return v;
  }
  void skip(size_t n) {
    if (at_ + n > bytes_.size()) throw Error(where_ + ": a message shorter than its fields (a corrupt bag)");
    at_ += n;
  }
  void text() { skip(u32()); }
  uint32_t count(size_t smallest) {
    const uint32_t n = u32();
    if (uint64_t(n) * smallest > bytes_.size() - at_)
      throw Error(where_ + ": a message states " + std::to_string(n) + " elements in " + std::to_string(bytes_.size()) +
                  " bytes (a corrupt bag)");
    return n;
  }

  std::string where_;
  std::vector<uint8_t> bytes_;
  size_t at_ = 0;
};

class Ros1Reader : public Reader {
 public:
  explicit Ros1Reader(const std::vector<std::string>& files) : files_(files) {
    if (files_.empty()) throw Error("no .bag file to read");
    // rosbag and cpp_common print their complaints through console_bridge;
    // the reader says what is wrong itself, in one line.
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
    for (const auto& f : files_) {
      RecordWalk(f).check();
      auto bag = std::make_unique<rosbag::Bag>();
      guarded(f, [&] { bag->open(f, rosbag::bagmode::Read); });
      bags_.push_back(std::move(bag));
    }
    std::map<std::string, TopicInfo> by_name;
    for (size_t b = 0; b < bags_.size(); ++b)
      guarded(files_[b], [&] {
        rosbag::View view(*bags_[b]);
        for (const rosbag::ConnectionInfo* c : view.getConnections()) {
          TopicInfo& t = by_name[c->topic];
          if (!t.type.empty() && t.type != c->datatype)
            throw Error("topic " + c->topic + " has two types (" + t.type + ", " + c->datatype + ")");
          t.name = c->topic, t.type = c->datatype, t.kind = kind_of(c->topic, c->datatype);
        }
        for (auto& [name, t] : by_name) t.messages += rosbag::View(*bags_[b], rosbag::TopicQuery(name)).size();
      });
    for (auto& [name, t] : by_name) topics_.push_back(t);
  }

  std::vector<TopicInfo> topics() const override { return topics_; }
  std::string path() const override { return files_.size() == 1 ? files_[0] : files_[0] + " (and " + std::to_string(files_.size() - 1) + " more)"; }

  void read(const std::vector<std::string>& topics, const Visitor& visitor, bool clouds_headers_only) override {
    std::map<std::string, MessageKind> kinds;
    for (const auto& name : topics) {
      const auto it = std::find_if(topics_.begin(), topics_.end(), [&](const TopicInfo& t) { return t.name == name; });
      if (it == topics_.end()) throw Error(path() + ": no topic " + name);
      if (it->kind == MessageKind::other)
        throw Error(path() + ": topic " + name + " is a " + it->type + ", not a point cloud, tf, odometry or pose");
      kinds[name] = it->kind;
    }
    rosbag::View view;
    for (auto& b : bags_) view.addQuery(*b, rosbag::TopicQuery(topics));
    guarded(path(), [&] {
      for (const rosbag::MessageInstance& m : view) {
        const std::string& topic = m.getTopic();
        const MessageKind kind = kinds.at(topic);
        if (kind == MessageKind::point_cloud && visitor.cloud) {
          if (!checked_.count(topic)) CountCheck(m, path() + ": topic " + topic).point_cloud();
          visitor.cloud(topic, from_ros(*must<sensor_msgs::PointCloud2>(m), clouds_headers_only));
        } else if ((kind == MessageKind::tf || kind == MessageKind::tf_static) && visitor.tf) {
          if (!checked_.count(topic)) CountCheck(m, path() + ": topic " + topic).tf_message();
          const auto msg = must<tf2_msgs::TFMessage>(m);
          std::vector<FrameTransform> out;
          for (const auto& t : msg->transforms) {
            geometry_msgs::Point p;
            p.x = t.transform.translation.x, p.y = t.transform.translation.y, p.z = t.transform.translation.z;
            out.push_back({seconds(t.header.stamp), t.header.frame_id, t.child_frame_id,
                           to_isometry(p, t.transform.rotation, path() + ": " + topic)});
          }
          visitor.tf(topic, std::move(out), kind == MessageKind::tf_static);
        } else if (kind == MessageKind::odometry && visitor.pose) {
          const auto msg = must<nav_msgs::Odometry>(m);
          visitor.pose(topic, {seconds(msg->header.stamp), msg->header.frame_id, msg->child_frame_id,
                               to_isometry(msg->pose.pose.position, msg->pose.pose.orientation, path() + ": " + topic)});
        } else if (kind == MessageKind::pose_stamped && visitor.pose) {
          const auto msg = must<geometry_msgs::PoseStamped>(m);
          visitor.pose(topic, {seconds(msg->header.stamp), msg->header.frame_id, "",
                               to_isometry(msg->pose.position, msg->pose.orientation, path() + ": " + topic)});
        }
      }
    });
    // A topic read through once has had its counts checked: a second pass
    // (the clouds kept, after their headers) reads the same bytes.
    checked_.insert(topics.begin(), topics.end());
  }

 private:
  template <class T>
  boost::shared_ptr<T> must(const rosbag::MessageInstance& m) const {
    auto msg = m.instantiate<T>();
    if (!msg) throw Error(path() + ": topic " + m.getTopic() + " does not decode as " + m.getDataType() + " (another message definition?)");
    return msg;
  }

  // rosbag and the serializers throw their own exceptions; say them as every
  // other error: the file, then what is wrong.
  template <class F>
  static void guarded(const std::string& file, F&& f) {
    try {
      f();
    } catch (const rosbag::BagUnindexedException&) {
      throw Error(file + ": the bag is not indexed (recording was cut short?); repair it with `rosbag reindex`");
    } catch (const rosbag::BagException& e) {
      throw Error(file + ": not a readable ROS 1 bag (" + std::string(e.what()) + ")");
    } catch (const ros::Exception& e) {
      throw Error(file + ": a message that does not decode (" + std::string(e.what()) + "); a truncated bag?");
    } catch (const std::bad_alloc&) {
      throw Error(file + ": a message too large to hold in memory (a corrupt length?)");
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      // ros::Time throws std::runtime_error for a stamp past 2^32 s (an
      // index entry's nanoseconds carried into its seconds).
      throw Error(file + ": not a readable ROS 1 bag (" + std::string(e.what()) + ")");
    }
  }

  std::vector<std::string> files_;
  std::vector<std::unique_ptr<rosbag::Bag>> bags_;
  std::vector<TopicInfo> topics_;
  std::set<std::string> checked_;
};

class Ros1Writer : public Writer {
 public:
  Ros1Writer(const std::string& file, bool compress) : file_(file) {
    try {
      bag_.open(file, rosbag::bagmode::Write);
      if (compress) bag_.setCompression(rosbag::compression::LZ4);
    } catch (const rosbag::BagException& e) {
      throw Error(file + ": cannot write (" + std::string(e.what()) + ")");
    }
  }
  ~Ros1Writer() override {
    try {
      close();
    } catch (...) {
    }
  }

  void write_cloud(const std::string& topic, const Cloud& c, double t) override {
    sensor_msgs::PointCloud2 m;
    m.header.stamp = ros_time(c.stamp, file_), m.header.frame_id = c.frame_id;
    m.height = c.height, m.width = c.width, m.point_step = c.point_step, m.row_step = c.row_step;
    m.is_bigendian = c.is_bigendian, m.is_dense = c.is_dense;
    for (const auto& f : c.fields) {
      sensor_msgs::PointField pf;
      pf.name = f.name, pf.offset = f.offset, pf.datatype = f.datatype, pf.count = f.count;
      m.fields.push_back(pf);
    }
    m.data = c.data;
    put(topic, t, m);
  }
  void write_tf(const std::string& topic, const std::vector<FrameTransform>& transforms, double t) override {
    tf2_msgs::TFMessage m;
    for (const auto& f : transforms) {
      geometry_msgs::TransformStamped ts;
      ts.header.stamp = ros_time(f.stamp, file_), ts.header.frame_id = f.parent_frame, ts.child_frame_id = f.child_frame;
      ts.transform.translation.x = f.transform.translation().x();
      ts.transform.translation.y = f.transform.translation().y();
      ts.transform.translation.z = f.transform.translation().z();
      ts.transform.rotation = to_quaternion(f.transform.linear());
      m.transforms.push_back(ts);
    }
    put(topic, t, m);
  }
  void write_odometry(const std::string& topic, const StampedPose& p, double t) override {
    nav_msgs::Odometry m;
    m.header.stamp = ros_time(p.stamp, file_), m.header.frame_id = p.frame_id, m.child_frame_id = p.child_frame;
    m.pose.pose.position = to_point(p.pose.translation());
    m.pose.pose.orientation = to_quaternion(p.pose.linear());
    put(topic, t, m);
  }
  void write_pose_stamped(const std::string& topic, const StampedPose& p, double t) override {
    geometry_msgs::PoseStamped m;
    m.header.stamp = ros_time(p.stamp, file_), m.header.frame_id = p.frame_id;
    m.pose.position = to_point(p.pose.translation());
    m.pose.orientation = to_quaternion(p.pose.linear());
    put(topic, t, m);
  }
  void close() override {
    if (!bag_.isOpen()) return;
    try {
      bag_.close();
    } catch (const rosbag::BagException& e) {
      throw Error(file_ + ": cannot finish the bag (" + std::string(e.what()) + ")");
    }
  }

 private:
  template <class M>
  void put(const std::string& topic, double t, const M& m) {
    try {
      bag_.write(topic, ros_time(t, file_), m);
    } catch (const rosbag::BagException& e) {
      throw Error(file_ + ": cannot write topic " + topic + " (" + std::string(e.what()) + ")");
    }
  }

  std::string file_;
  rosbag::Bag bag_;
};

}  // namespace

std::unique_ptr<Reader> open_ros1(const std::vector<std::string>& bag_files) { return std::make_unique<Ros1Reader>(bag_files); }

std::unique_ptr<Writer> create_ros1(const std::string& bag_file, bool compress) {
  return std::make_unique<Ros1Writer>(bag_file, compress);
}

}  // namespace lista::bag
