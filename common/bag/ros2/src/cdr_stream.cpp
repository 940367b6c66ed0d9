#include "cdr_stream.hpp"

#include <lista/error.hpp>
#include <lista_io/byte_load.hpp>

#include <algorithm>
#include <cstring>

namespace lista::bag::cdr {
namespace {

constexpr bool host_big_endian() {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  return true;
#else
  return false;
#endif
}

}  // namespace

Input::Input(const uint8_t* data, size_t size, const char* type) : data_(data), size_(size), type_(type) {
  if (size < 4) fail("encapsulation header", "message of " + std::to_string(size) + " bytes is shorter than the 4-byte header");
  if (data[0] != 0 || data[1] > 1)
    fail("encapsulation header", "unsupported encapsulation " + std::to_string(data[0]) + "," + std::to_string(data[1]) +
                                     " (only CDR_LE and CDR_BE, XCDR1)");
  const bool big = data[1] == 0;
  swap_ = big != host_big_endian();
}

void Input::fail(const char* field, const std::string& why) const {
  throw Error(std::string("CDR ") + type_ + ": " + field + ": " + why);
}

const uint8_t* Input::take(size_t n, size_t alignment, const char* field) {
  const size_t pad = (alignment - (pos_ - 4) % alignment) % alignment;
  if (pad > size_ - pos_ || n > size_ - pos_ - pad)
    fail(field, "truncated at byte " + std::to_string(pos_) + " of " + std::to_string(size_));
  pos_ += pad;
  const uint8_t* p = data_ + pos_;
  pos_ += n;
  return p;
}

uint8_t Input::u8(const char* field) { return *take(1, 1, field); }
uint32_t Input::u32(const char* field) { return io::load_bytes<uint32_t>(take(4, 4, field), swap_); }
int32_t Input::i32(const char* field) { return io::load_bytes<int32_t>(take(4, 4, field), swap_); }
double Input::f64(const char* field) { return io::load_bytes<double>(take(8, 8, field), swap_); }

bool Input::boolean(const char* field) {
  const uint8_t v = u8(field);
  if (v > 1) fail(field, "boolean byte is " + std::to_string(v));
  return v == 1;
}

std::string Input::string(const char* field) {
  const uint32_t n = count(field, 1);
  if (n == 0) fail(field, "string length 0 (it must count its NUL terminator)");
  const uint8_t* p = take(n, 1, field);
  if (p[n - 1] != 0) fail(field, "string is not NUL-terminated");
  return std::string(reinterpret_cast<const char*>(p), n - 1);
}

uint32_t Input::count(const char* field, size_t min_element_bytes) {
  const uint32_t n = u32(field);
  if (min_element_bytes && n > (size_ - pos_) / min_element_bytes)
    fail(field, "declares " + std::to_string(n) + " elements but only " + std::to_string(size_ - pos_) + " bytes are left");
  return n;
}

void Input::bytes(const char* field, std::vector<uint8_t>& out, bool keep) {
  const uint32_t n = count(field, 1);
  const uint8_t* p = take(n, 1, field);
  if (keep) out.assign(p, p + n);
}

Output::Output(bool big_endian) : buf_{0, uint8_t(big_endian ? 0 : 1), 0, 0}, swap_(big_endian != host_big_endian()) {}

void Output::put(const void* v, size_t n) {
  buf_.resize(buf_.size() + (n - (buf_.size() - 4) % n) % n, 0);  // alignment padding
  const size_t at = buf_.size();
  buf_.resize(at + n);
  std::memcpy(buf_.data() + at, v, n);
  if (swap_) std::reverse(buf_.begin() + at, buf_.end());
}

void Output::u8(uint8_t v) { put(&v, 1); }
void Output::u32(uint32_t v) { put(&v, 4); }
void Output::i32(int32_t v) { put(&v, 4); }
void Output::f64(double v) { put(&v, 8); }

void Output::string(const std::string& s) {
  u32(static_cast<uint32_t>(s.size() + 1));
  buf_.insert(buf_.end(), s.begin(), s.end());
  buf_.push_back(0);
}

void Output::bytes(const std::vector<uint8_t>& b) {
  u32(static_cast<uint32_t>(b.size()));
  buf_.insert(buf_.end(), b.begin(), b.end());
}

}  // namespace lista::bag::cdr
