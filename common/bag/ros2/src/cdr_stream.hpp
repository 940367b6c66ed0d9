// XCDR1 (classic CDR) byte streams as ROS 2 serialises messages: a 4-byte
// encapsulation header (00 01 little endian, 00 00 big endian), then
// primitives aligned to their size counted from the byte after the header,
// strings as uint32 length (NUL included) + bytes, sequences as uint32 count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lista::bag::cdr {

// Bounds-checked reader; every failure is a lista::Error that names the
// message type and the field being decoded.
class Input {
 public:
  Input(const uint8_t* data, size_t size, const char* type);

  uint8_t u8(const char* field);
  uint32_t u32(const char* field);
  int32_t i32(const char* field);
  double f64(const char* field);
  bool boolean(const char* field);
  std::string string(const char* field);
  // A sequence's count, refused when even `min_element_bytes` per element
  // would not fit in the bytes left (no allocation from a forged count).
  uint32_t count(const char* field, size_t min_element_bytes);
  // A uint8 sequence's bytes; with keep false they are only skipped.
  void bytes(const char* field, std::vector<uint8_t>& out, bool keep);

  [[noreturn]] void fail(const char* field, const std::string& why) const;

 private:
  const uint8_t* take(size_t n, size_t alignment, const char* field);
  const uint8_t* data_;
  size_t size_, pos_ = 4;
  bool swap_ = false;  // data in the other byte order than this machine
  const char* type_;
};

// Writer of the same layout, in either byte order.
class Output {
 public:
  explicit Output(bool big_endian = false);
  void u8(uint8_t v);
  void u32(uint32_t v);
  void i32(int32_t v);
  void f64(double v);
  void boolean(bool v) { u8(v ? 1 : 0); }
  void string(const std::string& s);
  void bytes(const std::vector<uint8_t>& b);
  std::vector<uint8_t> take() { return std::move(buf_); }

 private:
  void put(const void* v, size_t n);
  std::vector<uint8_t> buf_;
  bool swap_;
};

}  // namespace lista::bag::cdr
