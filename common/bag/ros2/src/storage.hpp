// What the bag layer needs from one rosbag2 storage file (.db3 or .mcap):
// its topics, and its serialised messages streamed in storage order. The
// storages know nothing of CDR; ros2_bag.cpp decodes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace lista::bag::ros2 {

struct StorageTopic {
  std::string name;
  std::string type;      // "sensor_msgs/msg/PointCloud2"; empty when the file has none
  std::string encoding;  // serialization_format / message_encoding: "cdr"
  uint64_t messages = 0;
};

// One serialised message; `data` lives until the callback returns.
using MessageSink = std::function<void(const StorageTopic& topic, int64_t time_ns, const uint8_t* data, size_t size)>;

class StorageReader {
 public:
  virtual ~StorageReader() = default;
  virtual const std::vector<StorageTopic>& topics() const = 0;  // one entry per name
  // Streams the messages of the topics named in `wanted`; others are skipped
  // without being copied or decompressed where the format allows.
  virtual void read(const std::set<std::string>& wanted, const MessageSink& sink) = 0;
  virtual const std::string& path() const = 0;
};

class StorageWriter {
 public:
  virtual ~StorageWriter() = default;
  // A topic's first message declares its type.
  virtual void write(const std::string& topic, const std::string& type, int64_t time_ns, const std::vector<uint8_t>& cdr) = 0;
  // Finishes the file and gives it its final name; later calls do nothing.
  virtual void close() = 0;
};

std::unique_ptr<StorageReader> open_sqlite(const std::string& file);
std::unique_ptr<StorageWriter> create_sqlite(const std::string& file);

// MCAP writer choices; the tests use all of them.
enum class McapCompression { none, zstd, lz4 };
struct McapOptions {
  McapCompression compression = McapCompression::zstd;
  size_t chunk_bytes = 4u << 20;    // a chunk is closed once its records pass this
  bool summary = true;              // Schema/Channel/Statistics summary after DataEnd
  std::string message_encoding = "cdr";
};
std::unique_ptr<StorageReader> open_mcap(const std::string& file);
std::unique_ptr<StorageWriter> create_mcap(const std::string& file, const McapOptions& options = {});

// Writes `file` under a temporary name and renames it over `file` (no
// half-written file under the final name); throws naming the file.
void write_file_atomically(const std::string& file, const std::string& text);

}  // namespace lista::bag::ros2
