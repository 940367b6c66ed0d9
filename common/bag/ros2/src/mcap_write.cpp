// MCAP writer in rosbag2's layout: Header, then chunks holding each new
// topic's Schema and Channel ahead of its messages, DataEnd, a summary
// (Schemas, Channels, Statistics) and the Footer. CRCs are written as 0,
// which the specification reads as "not computed".
#include "mcap_format.hpp"

#include <lista/error.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>

namespace lista::bag::ros2 {
namespace {

using namespace mcap;

struct ChannelOut {
  uint16_t id = 0, schema = 0;
  std::string topic;
  uint32_t sequence = 0;
  uint64_t messages = 0;
};

class McapWriter : public StorageWriter {
 public:
  McapWriter(const std::string& file, const McapOptions& options)
      : file_(file), part_(file + ".part"), options_(options), f_(std::fopen(part_.c_str(), "wb")) {
    if (!f_) throw Error(part_ + ": cannot create: " + std::strerror(errno));
    std::vector<uint8_t> out(kMagic, kMagic + 8);
    Content().string("ros2").string("lista").append_to(out, kHeader);
    put(out);
  }
  ~McapWriter() override {
    if (f_) std::fclose(f_);
    if (!closed_) std::remove(part_.c_str());  // never closed: nothing looks complete
  }

  void write(const std::string& topic, const std::string& type, int64_t time_ns, const std::vector<uint8_t>& cdr) override {
    if (closed_) throw Error(file_ + ": written after close");
    auto it = channels_.find(topic);
    if (it == channels_.end()) it = add_channel(topic, type);
    ChannelOut& ch = it->second;
    const uint64_t t = static_cast<uint64_t>(time_ns);
    Content m;
    m.u16(ch.id).u32(ch.sequence++).u64(t).u64(t);
    m.buf.insert(m.buf.end(), cdr.begin(), cdr.end());
    m.append_to(chunk_, kMessage);
    ++ch.messages;
    chunk_start_ = chunk_messages_ ? std::min(chunk_start_, t) : t;
    chunk_end_ = chunk_messages_ ? std::max(chunk_end_, t) : t;
    first_ = messages_ ? std::min(first_, t) : t;
    last_ = messages_ ? std::max(last_, t) : t;
    ++chunk_messages_;
    ++messages_;
    if (chunk_.size() >= options_.chunk_bytes) flush_chunk();
  }

  void close() override {
    if (closed_) return;
    flush_chunk();
    std::vector<uint8_t> out;
    Content().u32(0).append_to(out, kDataEnd);
    uint64_t summary_start = 0;
    if (options_.summary) {
      summary_start = written_ + out.size();
      for (const auto& [type, id] : schemas_) schema_content(id, type).append_to(out, kSchema);
      for (const auto& [topic, ch] : channels_) channel_content(ch).append_to(out, kChannel);
      Content stats;
      stats.u64(messages_).u16(static_cast<uint16_t>(schemas_.size())).u32(static_cast<uint32_t>(channels_.size()));
      stats.u32(0).u32(0).u32(chunks_).u64(first_).u64(last_);
      Content counts;
      for (const auto& [topic, ch] : channels_) counts.u16(ch.id).u64(ch.messages);
      stats.bytes32(counts.buf.data(), counts.buf.size()).append_to(out, kStatistics);
    }
    Content().u64(summary_start).u64(0).u32(0).append_to(out, kFooter);
    out.insert(out.end(), kMagic, kMagic + 8);
    put(out);
    const int rc = std::fclose(f_);
    f_ = nullptr;
    if (rc != 0) throw Error(part_ + ": cannot finish writing: " + std::strerror(errno));
    if (std::rename(part_.c_str(), file_.c_str()) != 0) throw Error(file_ + ": cannot rename " + part_ + " to it");
    closed_ = true;
  }

 private:
  std::map<std::string, ChannelOut>::iterator add_channel(const std::string& topic, const std::string& type) {
    auto s = schemas_.find(type);
    if (s == schemas_.end()) {
      s = schemas_.emplace(type, static_cast<uint16_t>(schemas_.size() + 1)).first;
      schema_content(s->second, type).append_to(chunk_, kSchema);
    }
    if (channels_.size() >= 65535) throw Error(file_ + ": more than 65535 topics");
    ChannelOut ch;
    ch.id = static_cast<uint16_t>(channels_.size() + 1);
    ch.schema = s->second;
    ch.topic = topic;
    channel_content(ch).append_to(chunk_, kChannel);
    return channels_.emplace(topic, ch).first;
  }

  Content schema_content(uint16_t id, const std::string& type) const {
    // rosbag2 stores the .msg text here; readers of CDR by type name (LiSTA,
    // rosbag2 itself) do not need it.
    const std::string text = "# " + type + " (definition not stored by LiSTA)\n";
    return std::move(Content().u16(id).string(type).string("ros2msg").bytes32(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  }

  Content channel_content(const ChannelOut& ch) const {
    Content qos;
    qos.string("offered_qos_profiles").string("");
    Content c;
    c.u16(ch.id).u16(ch.schema).string(ch.topic).string(options_.message_encoding).bytes32(qos.buf.data(), qos.buf.size());
    return c;
  }

  void flush_chunk() {
    if (chunk_.empty()) return;
    const std::vector<uint8_t> packed = compress_chunk(options_.compression, chunk_);
    Content c;
    c.u64(chunk_messages_ ? chunk_start_ : 0).u64(chunk_messages_ ? chunk_end_ : 0).u64(chunk_.size()).u32(0);
    c.string(compression_name(options_.compression)).bytes64(packed.data(), packed.size());
    std::vector<uint8_t> out;
    c.append_to(out, kChunk);
    put(out);
    ++chunks_;
    chunk_.clear();
    chunk_messages_ = 0;
  }

  void put(const std::vector<uint8_t>& bytes) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), f_) != bytes.size()) throw Error(part_ + ": cannot write: " + std::strerror(errno));
    written_ += bytes.size();
  }

  std::string file_, part_;
  McapOptions options_;
  std::FILE* f_;
  uint64_t written_ = 0;
  std::map<std::string, uint16_t> schemas_;  // type -> id
  std::map<std::string, ChannelOut> channels_;  // topic -> channel
  std::vector<uint8_t> chunk_;
  uint64_t chunk_start_ = 0, chunk_end_ = 0, chunk_messages_ = 0;
  uint64_t first_ = 0, last_ = 0, messages_ = 0;
  uint32_t chunks_ = 0;
  bool closed_ = false;
};

}  // namespace

std::unique_ptr<StorageWriter> create_mcap(const std::string& file, const McapOptions& options) {
  return std::make_unique<McapWriter>(file, options);
}

}  // namespace lista::bag::ros2
