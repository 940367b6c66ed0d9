// The pieces of the MCAP container (https://mcap.dev/spec) that the reader
// and writer share: magic, opcodes, a bounds-checked little-endian cursor
// over a record's content, a record builder, and chunk (de)compression.
#pragma once

#include "storage.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lista::bag::ros2::mcap {

constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr size_t kRecordHead = 9;   // opcode uint8 + content length uint64
constexpr size_t kFooterContent = 20;

enum Op : uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kMessageIndex = 0x07, kChunkIndex = 0x08, kAttachment = 0x09, kAttachmentIndex = 0x0A,
  kStatistics = 0x0B, kMetadata = 0x0C, kMetadataIndex = 0x0D, kSummaryOffset = 0x0E, kDataEnd = 0x0F,
};

uint64_t load_u64(const uint8_t* p);

// Reads one record's content; failures name the file, the record and where
// it starts.
class Cursor {
 public:
  Cursor(const uint8_t* data, size_t size, const std::string& file, const char* record, uint64_t offset)
      : data_(data), size_(size), file_(file), record_(record), offset_(offset) {}
  uint16_t u16(const char* field);
  uint32_t u32(const char* field);
  uint64_t u64(const char* field);
  std::string string(const char* field);
  // uint32- or uint64-prefixed bytes, returned in place.
  const uint8_t* bytes32(const char* field, size_t& n);
  const uint8_t* bytes64(const char* field, size_t& n);
  void skip_map(const char* field);  // uint32 byte length + entries
  const uint8_t* rest(size_t& n);    // all that is left
  [[noreturn]] void fail(const char* field, const std::string& why) const;

 private:
  const uint8_t* take(size_t n, const char* field);
  const uint8_t* data_;
  size_t size_, pos_ = 0;
  const std::string& file_;
  const char* record_;
  uint64_t offset_;
};

// Builds one record's content, little endian.
class Content {
 public:
  Content& u16(uint16_t v) { return le(v, 2); }
  Content& u32(uint32_t v) { return le(v, 4); }
  Content& u64(uint64_t v) { return le(v, 8); }
  Content& string(const std::string& s);
  Content& bytes32(const uint8_t* p, size_t n);
  Content& bytes64(const uint8_t* p, size_t n);
  // Appends the whole record (opcode, length, content) to `out`.
  void append_to(std::vector<uint8_t>& out, Op op) const;
  std::vector<uint8_t> buf;

 private:
  Content& le(uint64_t v, int n);
};

// Chunk records: `compression` is "", "zstd" or "lz4" (LZ4 frame format).
// Refuses an uncompressed_size the compressed bytes cannot hold or over
// 1 GiB before allocating; errors name `where` (file and chunk offset).
std::vector<uint8_t> decompress_chunk(const std::string& compression, const uint8_t* data, size_t size,
                                      uint64_t uncompressed_size, const std::string& where);
std::vector<uint8_t> compress_chunk(McapCompression compression, const std::vector<uint8_t>& records);
const char* compression_name(McapCompression compression);

}  // namespace lista::bag::ros2::mcap
