// MCAP reader: topics from the summary section when the file has one (its
// Statistics give the counts), otherwise from one pass over the data; then
// messages streamed record by record from the start, one chunk in memory at
// a time, until DataEnd or the Footer.
#include "mcap_format.hpp"

#include <lista/error.hpp>

#include <cstdio>
#include <cstring>
#include <map>

namespace lista::bag::ros2 {
namespace {

using namespace mcap;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

struct Channel {
  size_t topic = 0;  // index into topics_
};

class McapReader : public StorageReader {
 public:
  explicit McapReader(const std::string& file) : file_(file), f_(std::fopen(file.c_str(), "rb")) {
    if (!f_) throw Error(file_ + ": cannot open: " + std::strerror(errno));
    if (fseeko(f_.get(), 0, SEEK_END) != 0) throw Error(file_ + ": cannot seek");
    size_ = static_cast<uint64_t>(ftello(f_.get()));
    uint8_t magic[8];
    if (size_ < 8 || (read_at(0, magic, 8), std::memcmp(magic, kMagic, 8) != 0))
      throw Error(file_ + ": not an MCAP file (no MCAP magic at its start)");
    if (!read_summary()) walk_data(nullptr, [this](const Channel& c, uint64_t, const uint8_t*, size_t) { ++topics_[c.topic].messages; });
  }

  const std::vector<StorageTopic>& topics() const override { return topics_; }
  const std::string& path() const override { return file_; }

  void read(const std::set<std::string>& wanted, const MessageSink& sink) override {
    std::vector<bool> want(topics_.size());
    bool any = false;
    for (size_t i = 0; i < topics_.size(); ++i) any |= (want[i] = wanted.count(topics_[i].name) > 0);
    if (!any) return;
    walk_data(&want, [&](const Channel& c, uint64_t time, const uint8_t* data, size_t n) {
      sink(topics_[c.topic], static_cast<int64_t>(time), data, n);
    });
  }

 private:
  using OnMessage = std::function<void(const Channel&, uint64_t log_time, const uint8_t*, size_t)>;

  void read_at(uint64_t at, void* out, size_t n) {
    if (fseeko(f_.get(), static_cast<off_t>(at), SEEK_SET) != 0 || std::fread(out, 1, n, f_.get()) != n)
      throw Error(file_ + ": cannot read " + std::to_string(n) + " bytes at byte " + std::to_string(at));
  }

  // Calls on(opcode, content, size, offset) for the records in [from, end)
  // whose opcode `load` accepts (others are skipped unread); stops after
  // DataEnd or Footer when `data` is set (the data section has no end
  // offset of its own).
  template <class Load, class On>
  void walk(uint64_t from, uint64_t end, bool data, Load load, On on) {
    uint64_t at = from;
    while (true) {
      if (end - at < kRecordHead) {
        if (data) throw Error(file_ + ": truncated MCAP: ends at byte " + std::to_string(at) + " without a DataEnd or Footer record");
        return;
      }
      uint8_t head[kRecordHead];
      read_at(at, head, kRecordHead);
      const uint64_t len = load_u64(head + 1);
      if (len > end - at - kRecordHead)
        throw Error(file_ + ": truncated MCAP: record (opcode " + std::to_string(head[0]) + ") at byte " + std::to_string(at) +
                    " declares " + std::to_string(len) + " bytes, past the end");
      if (data && (head[0] == kDataEnd || head[0] == kFooter)) return;
      if (load(head[0])) {
        buf_.resize(len);
        if (len) read_at(at + kRecordHead, buf_.data(), len);
        on(head[0], buf_.data(), buf_.size(), at);
      }
      at += kRecordHead + len;
    }
  }

  // The summary section's Schema, Channel and Statistics records; false
  // when the file has no summary or it lacks message counts.
  bool read_summary() {
    constexpr uint64_t tail = kRecordHead + kFooterContent + 8;
    if (size_ < 8 + tail) return false;
    uint8_t foot[tail];
    read_at(size_ - tail, foot, tail);
    if (foot[0] != kFooter || load_u64(foot + 1) != kFooterContent || std::memcmp(foot + tail - 8, kMagic, 8) != 0) return false;
    const uint64_t start = load_u64(foot + kRecordHead), footer_at = size_ - tail;
    if (start == 0) return false;
    if (start < 8 || start > footer_at) throw Error(file_ + ": MCAP Footer: summary_start " + std::to_string(start) + " is outside the file");
    bool counted = false;
    std::map<uint16_t, uint64_t> counts;
    walk(start, footer_at, false, [](uint8_t op) { return op == kSchema || op == kChannel || op == kStatistics; },
         [&](uint8_t op, const uint8_t* p, size_t n, uint64_t at) {
           if (op != kStatistics) return on_definition(op, p, n, at);
           Cursor c(p, n, file_, "Statistics", at);
           c.u64("message_count");
           c.u16("schema_count");
           for (const char* f : {"channel_count", "attachment_count", "metadata_count", "chunk_count"}) c.u32(f);
           c.u64("message_start_time");
           c.u64("message_end_time");
           size_t len = 0;
           const uint8_t* m = c.bytes32("channel_message_counts", len);
           Cursor entries(m, len, file_, "Statistics", at);
           for (size_t left = len; left > 0; left -= 10) {
             if (left < 10) entries.fail("channel_message_counts", "truncated entry");
             const uint16_t id = entries.u16("channel_message_counts");
             counts[id] += entries.u64("channel_message_counts");
           }
           counted = true;
         });
    if (!counted) return false;
    // Counts of channels the summary does not define cannot be placed: count by reading instead.
    for (const auto& [id, n] : counts)
      if (!channels_.count(id)) return false;
    for (const auto& [id, n] : counts) topics_[channels_[id].topic].messages += n;
    return true;
  }

  // Schema and Channel records, wherever they appear: a channel's topic
  // joins topics_ on first sight, by name.
  void on_definition(uint8_t op, const uint8_t* p, size_t n, uint64_t at) {
    if (op == kSchema) {
      Cursor c(p, n, file_, "Schema", at);
      const uint16_t id = c.u16("id");
      schemas_[id] = c.string("name");
      return;
    }
    Cursor c(p, n, file_, "Channel", at);
    const uint16_t id = c.u16("id");
    const uint16_t schema = c.u16("schema_id");
    const std::string topic = c.string("topic");
    const std::string encoding = c.string("message_encoding");
    c.skip_map("metadata");
    std::string type;
    if (schema != 0) {
      const auto s = schemas_.find(schema);
      if (s == schemas_.end()) c.fail("schema_id", "schema " + std::to_string(schema) + " is not defined before it");
      type = s->second;
    }
    auto [it, fresh] = index_.emplace(topic, topics_.size());
    if (fresh) topics_.push_back({topic, type, encoding, 0});
    channels_[id].topic = it->second;
  }

  // Streams the data section; `want` (by topic index) filters messages.
  void walk_data(const std::vector<bool>* want, const OnMessage& on) {
    const auto message = [&](const uint8_t* p, size_t n, uint64_t at) {
      Cursor c(p, n, file_, "Message", at);
      const uint16_t id = c.u16("channel_id");
      const auto it = channels_.find(id);
      if (it == channels_.end()) c.fail("channel_id", "channel " + std::to_string(id) + " is not defined before it");
      // A topic first defined mid-read was not asked for.
      if (want && (it->second.topic >= want->size() || !(*want)[it->second.topic])) return;
      c.u32("sequence");
      const uint64_t log_time = c.u64("log_time");
      c.u64("publish_time");
      size_t size = 0;
      const uint8_t* data = c.rest(size);
      on(it->second, log_time, data, size);
    };
    walk(8, size_, true, [](uint8_t op) { return op == kSchema || op == kChannel || op == kMessage || op == kChunk; },
         [&](uint8_t op, const uint8_t* p, size_t n, uint64_t at) {
           if (op == kMessage) return message(p, n, at);
           if (op != kChunk) return on_definition(op, p, n, at);
           Cursor c(p, n, file_, "Chunk", at);
           c.u64("message_start_time");
           c.u64("message_end_time");
           const uint64_t usize = c.u64("uncompressed_size");
           c.u32("uncompressed_crc");
           const std::string compression = c.string("compression");
           size_t len = 0;
           const uint8_t* records = c.bytes64("records", len);
           const std::string where = file_ + ": MCAP Chunk record at byte " + std::to_string(at);
           const std::vector<uint8_t> inner = decompress_chunk(compression, records, len, usize, where);
           // Offsets inside a chunk are reported as the chunk's own.
           for (size_t pos = 0; pos < inner.size();) {
             if (inner.size() - pos < kRecordHead) throw Error(where + ": truncated record inside the chunk");
             const uint8_t op_in = inner[pos];
             const uint64_t len_in = load_u64(&inner[pos + 1]);
             if (len_in > inner.size() - pos - kRecordHead)
               throw Error(where + ": record inside the chunk declares " + std::to_string(len_in) + " bytes, past its end");
             const uint8_t* q = &inner[pos + kRecordHead];
             if (op_in == kMessage) message(q, len_in, at);
             else if (op_in == kSchema || op_in == kChannel) on_definition(op_in, q, len_in, at);
             pos += kRecordHead + len_in;
           }
         });
  }

  std::string file_;
  std::unique_ptr<std::FILE, FileCloser> f_;
  uint64_t size_ = 0;
  std::vector<uint8_t> buf_;
  std::vector<StorageTopic> topics_;
  std::map<std::string, size_t> index_;
  std::map<uint16_t, std::string> schemas_;
  std::map<uint16_t, Channel> channels_;
};

}  // namespace

std::unique_ptr<StorageReader> open_mcap(const std::string& file) { return std::make_unique<McapReader>(file); }

}  // namespace lista::bag::ros2
