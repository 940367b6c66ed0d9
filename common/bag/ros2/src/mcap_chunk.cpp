// MCAP record coding and chunk compression (Debian's libzstd and liblz4).
#include "mcap_format.hpp"

#include <lista/error.hpp>

#include <lz4frame.h>
#define ZSTD_STATIC_LINKING_ONLY  // ZSTD_decompressBound
#include <zstd.h>

#include <memory>

namespace lista::bag::ros2::mcap {

uint64_t load_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | p[i];
  return v;
}

void Cursor::fail(const char* field, const std::string& why) const {
  throw Error(file_ + ": MCAP " + record_ + " record at byte " + std::to_string(offset_) + ": " + field + ": " + why);
}

const uint8_t* Cursor::take(size_t n, const char* field) {
  if (n > size_ - pos_) fail(field, "truncated (needs " + std::to_string(n) + " bytes, " + std::to_string(size_ - pos_) + " left)");
  const uint8_t* p = data_ + pos_;
  pos_ += n;
  return p;
}

uint16_t Cursor::u16(const char* field) {
  const uint8_t* p = take(2, field);
  return static_cast<uint16_t>(p[0] | p[1] << 8);
}
uint32_t Cursor::u32(const char* field) {
  const uint8_t* p = take(4, field);
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint64_t Cursor::u64(const char* field) { return load_u64(take(8, field)); }

std::string Cursor::string(const char* field) {
  size_t n = 0;
  const uint8_t* p = bytes32(field, n);
  return std::string(reinterpret_cast<const char*>(p), n);
}

const uint8_t* Cursor::bytes32(const char* field, size_t& n) {
  n = u32(field);
  return take(n, field);
}

const uint8_t* Cursor::bytes64(const char* field, size_t& n) {
  const uint64_t len = u64(field);
  if (len > size_ - pos_) fail(field, "declares " + std::to_string(len) + " bytes, " + std::to_string(size_ - pos_) + " left");
  n = static_cast<size_t>(len);
  return take(n, field);
}

void Cursor::skip_map(const char* field) {
  size_t n = 0;
  bytes32(field, n);
}

const uint8_t* Cursor::rest(size_t& n) {
  n = size_ - pos_;
  return take(n, "data");
}

Content& Content::le(uint64_t v, int n) {
  for (int i = 0; i < n; ++i) buf.push_back(static_cast<uint8_t>(v >> (8 * i)));
  return *this;
}

Content& Content::string(const std::string& s) { return bytes32(reinterpret_cast<const uint8_t*>(s.data()), s.size()); }

Content& Content::bytes32(const uint8_t* p, size_t n) {
  u32(static_cast<uint32_t>(n));
  buf.insert(buf.end(), p, p + n);
  return *this;
}

Content& Content::bytes64(const uint8_t* p, size_t n) {
  u64(n);
  buf.insert(buf.end(), p, p + n);
  return *this;
}

void Content::append_to(std::vector<uint8_t>& out, Op op) const {
  out.push_back(op);
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<uint8_t>(uint64_t(buf.size()) >> (8 * i)));
  out.insert(out.end(), buf.begin(), buf.end());
}

namespace {

constexpr uint64_t kMaxChunk = uint64_t(1) << 30;
// An LZ4 sequence expands at most ~255 times; beyond that the size is forged.
constexpr uint64_t kLz4MaxRatio = 256;

struct Lz4Context {
  LZ4F_dctx* ctx = nullptr;
  ~Lz4Context() { LZ4F_freeDecompressionContext(ctx); }
};

void lz4_decompress(const uint8_t* src, size_t n, uint8_t* dst, size_t usize, const std::string& where) {
  Lz4Context c;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&c.ctx, LZ4F_VERSION))) throw Error(where + ": out of memory for lz4");
  size_t in = 0, out = 0;
  while (in < n) {  // frames may be concatenated
    size_t dst_size = usize - out, src_size = n - in;
    const size_t hint = LZ4F_decompress(c.ctx, dst + out, &dst_size, src + in, &src_size, nullptr);
    if (LZ4F_isError(hint)) throw Error(where + ": lz4: " + LZ4F_getErrorName(hint));
    in += src_size;
    out += dst_size;
    if (hint != 0 && in == n) throw Error(where + ": lz4: truncated frame");
    if (hint != 0 && src_size == 0 && dst_size == 0)
      throw Error(where + ": lz4: holds more than the declared uncompressed_size " + std::to_string(usize));
  }
  if (out != usize)
    throw Error(where + ": lz4: " + std::to_string(out) + " bytes, uncompressed_size says " + std::to_string(usize));
}

}  // namespace

std::vector<uint8_t> decompress_chunk(const std::string& compression, const uint8_t* data, size_t size,
                                      uint64_t usize, const std::string& where) {
  if (usize > kMaxChunk) throw Error(where + ": uncompressed_size " + std::to_string(usize) + " is over 1 GiB");
  if (compression.empty()) {
    if (usize != size) throw Error(where + ": uncompressed chunk of " + std::to_string(size) + " bytes, uncompressed_size says " + std::to_string(usize));
    return std::vector<uint8_t>(data, data + size);
  }
  if (compression == "zstd") {
    const unsigned long long bound = ZSTD_decompressBound(data, size);
    if (bound == ZSTD_CONTENTSIZE_ERROR) throw Error(where + ": zstd: not a valid zstd frame");
    if (usize > bound) throw Error(where + ": uncompressed_size " + std::to_string(usize) + " is more than its zstd frames can hold");
    std::vector<uint8_t> out(usize);
    const size_t got = ZSTD_decompress(out.data(), out.size(), data, size);
    if (ZSTD_isError(got)) throw Error(where + ": zstd: " + ZSTD_getErrorName(got));
    if (got != usize) throw Error(where + ": zstd: " + std::to_string(got) + " bytes, uncompressed_size says " + std::to_string(usize));
    return out;
  }
  if (compression == "lz4") {
    if (usize > kLz4MaxRatio * size + 1024) throw Error(where + ": uncompressed_size " + std::to_string(usize) + " is more than its lz4 frame can hold");
    std::vector<uint8_t> out(usize);
    lz4_decompress(data, size, out.data(), out.size(), where);
    return out;
  }
  throw Error(where + ": unknown chunk compression '" + compression + "' (LiSTA reads '', 'zstd' and 'lz4')");
}

const char* compression_name(McapCompression compression) {
  switch (compression) {
    case McapCompression::zstd: return "zstd";
    case McapCompression::lz4: return "lz4";
    case McapCompression::none: break;
  }
  return "";
}

std::vector<uint8_t> compress_chunk(McapCompression compression, const std::vector<uint8_t>& records) {
  if (compression == McapCompression::none) return records;
  std::vector<uint8_t> out;
  size_t n = 0;
  if (compression == McapCompression::zstd) {
    out.resize(ZSTD_compressBound(records.size()));
    n = ZSTD_compress(out.data(), out.size(), records.data(), records.size(), 1);  // rosbag2's "fastest"
    if (ZSTD_isError(n)) throw Error(std::string("zstd: ") + ZSTD_getErrorName(n));
  } else {
    out.resize(LZ4F_compressFrameBound(records.size(), nullptr));
    n = LZ4F_compressFrame(out.data(), out.size(), records.data(), records.size(), nullptr);
    if (LZ4F_isError(n)) throw Error(std::string("lz4: ") + LZ4F_getErrorName(n));
  }
  out.resize(n);
  return out;
}

}  // namespace lista::bag::ros2::mcap
