#include "lzf.hpp"

#include <cstring>

namespace lista::io::lzf {

namespace {
constexpr size_t kMaxLiteral = 32;
constexpr size_t kMaxOffset = 1 << 13;        // 8192
constexpr size_t kMaxMatch = 2 + 7 + 255;     // 264
constexpr int kHashBits = 14;

inline uint32_t hash3(const uint8_t* p) {
  const uint32_t v = (uint32_t(p[0]) << 16) | (uint32_t(p[1]) << 8) | p[2];
  return (v * 2654435761u) >> (32 - kHashBits);
}
}  // namespace

void compress(const uint8_t* in, size_t n, std::vector<uint8_t>& out) {
  std::vector<int64_t> table(size_t(1) << kHashBits, -1);
  size_t lit_start = 0;  // first byte of the pending literal run
  auto flush_literals = [&](size_t end) {
    while (lit_start < end) {
      const size_t len = std::min(kMaxLiteral, end - lit_start);
      out.push_back(static_cast<uint8_t>(len - 1));
      out.insert(out.end(), in + lit_start, in + lit_start + len);
      lit_start += len;
    }
  };
  size_t i = 0;
  while (i + 2 < n) {
    const uint32_t h = hash3(in + i);
    const int64_t cand = table[h];
    table[h] = static_cast<int64_t>(i);
    if (cand >= 0 && i - size_t(cand) <= kMaxOffset && std::memcmp(in + cand, in + i, 3) == 0) {
      size_t len = 3;
      const size_t limit = std::min(kMaxMatch, n - i);
      while (len < limit && in[cand + len] == in[i + len]) ++len;
      flush_literals(i);
      const size_t off = i - size_t(cand) - 1;
      const size_t l = len - 2;
      if (l < 7) {
        out.push_back(static_cast<uint8_t>((off >> 8) | (l << 5)));
      } else {
        out.push_back(static_cast<uint8_t>((off >> 8) | (7 << 5)));
        out.push_back(static_cast<uint8_t>(l - 7));
      }
      out.push_back(static_cast<uint8_t>(off & 0xff));
      // Index a few positions inside the match so later repeats are found.
      for (size_t k = i + 1; k < i + len && k + 2 < n; ++k) table[hash3(in + k)] = int64_t(k);
      i += len;
      lit_start = i;
    } else {
      ++i;
    }
  }
  flush_literals(n);
}

bool decompress(const uint8_t* in, size_t n, uint8_t* out, size_t out_size) {
  const uint8_t* ip = in;
  const uint8_t* const in_end = in + n;
  uint8_t* op = out;
  uint8_t* const out_end = out + out_size;
  while (ip < in_end) {
    const unsigned ctrl = *ip++;
    if (ctrl < 32) {  // literal run
      const size_t len = ctrl + 1;
      if (size_t(in_end - ip) < len || size_t(out_end - op) < len) return false;
      std::memcpy(op, ip, len);
      op += len;
      ip += len;
    } else {  // back reference
      size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_end) return false;
        len += *ip++;
      }
      if (ip >= in_end) return false;
      const size_t back = ((size_t(ctrl) & 0x1f) << 8) + *ip++ + 1;
      len += 2;
      if (back > size_t(op - out) || size_t(out_end - op) < len) return false;
      const uint8_t* ref = op - back;
      for (size_t k = 0; k < len; ++k) op[k] = ref[k];  // may overlap: byte by byte
      op += len;
    }
  }
  return op == out_end;
}

}  // namespace lista::io::lzf
