// PCD reading: header parsing plus the ascii / binary / binary_compressed
// payloads, any field sizes, types and counts (padding fields included).
#include "pcd_format.hpp"
#include "lzf.hpp"
#include "text_util.hpp"

#include <cctype>
#include <lista/error.hpp>
#include <lista_io/byte_load.hpp>
#include <lista_io/pcd.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

namespace lista::io {
namespace detail {

// Case-insensitive: PDAL and CloudCompare write "X", "Intensity".
int PcdData::find(const std::string& name) const {
  auto same = [&](const std::string& field) {
    return field.size() == name.size() &&
           std::equal(field.begin(), field.end(), name.begin(), [](char a, char b) {
             return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
           });
  };
  for (size_t f = 0; f < fields.size(); ++f)
    if (same(fields[f].name)) return static_cast<int>(f);
  return -1;
}

namespace {

// The numbers after VIEWPOINT: tx ty tz qw qx qy qz.
template <class Fail>
Eigen::Isometry3d parse_viewpoint(const std::vector<std::string>& tok, const Fail& fail) {
  if (tok.size() != 7) throw fail("VIEWPOINT needs 7 numbers: tx ty tz qw qx qy qz");
  double v[7];
  for (int k = 0; k < 7; ++k)
    if (!parse_double(tok[k], v[k]) || !std::isfinite(v[k]))
      throw fail("VIEWPOINT: '" + tok[k] + "' is not a finite number");
  Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
  if (std::abs(q.norm() - 1.0) > 1e-3) throw fail("VIEWPOINT quaternion is not unit length");
  q.normalize();
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = q.toRotationMatrix();
  t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return t;
}

template <class T>
double load_as(const uint8_t* p) {
  return static_cast<double>(load_bytes<T>(p));
}
}  // namespace

double PcdData::value(int f, size_t i, int e) const {
  const PcdField& fd = fields[f];
  if (encoding == "ascii") return ascii[i * row_values + ascii_column[f] + e];
  const uint8_t* p = base[f] + i * step[f] + size_t(e) * fd.size;
  switch (fd.type) {
    case 'F': return fd.size == 4 ? load_as<float>(p) : load_as<double>(p);
    case 'U':
      switch (fd.size) {
        case 1: return load_as<uint8_t>(p);
        case 2: return load_as<uint16_t>(p);
        case 4: return load_as<uint32_t>(p);
        default: return load_as<uint64_t>(p);
      }
    default:
      switch (fd.size) {
        case 1: return load_as<int8_t>(p);
        case 2: return load_as<int16_t>(p);
        case 4: return load_as<int32_t>(p);
        default: return load_as<int64_t>(p);
      }
  }
}

namespace {

// What the header says of the payload, and where the payload starts.
struct PcdHeader {
  std::vector<std::string> names;
  std::vector<int> sizes, counts;
  std::vector<char> types;
  long long width = -1, height = -1, points = -1;
  size_t payload = 0;  // byte offset of the data after the DATA line
  int lines = 0;       // header lines read
};

// "path:line: what", the line being the one read last.
Error failure(const std::string& path, int line, const std::string& what) {
  return Error(path + ":" + std::to_string(line) + ": " + what);
}

// Header: one keyword per line until DATA; sets d's viewpoint and encoding.
PcdHeader parse_header(const std::string& path, PcdData& d) {
  const std::string& bytes = d.file_bytes;
  PcdHeader h;
  auto fail = [&](const std::string& what) { return failure(path, h.lines, what); };
  while (true) {
    if (h.payload >= bytes.size()) throw Error(path + ": not a PCD file (no DATA line in the header)");
    size_t eol = bytes.find('\n', h.payload);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(h.payload, eol - h.payload);
    h.payload = std::min(bytes.size(), eol + 1);
    ++h.lines;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::vector<std::string> tok = split_ws(line);
    if (tok.empty()) continue;
    const std::string key = tok[0];
    tok.erase(tok.begin());
    auto ints = [&](std::vector<int>& out) {
      out.clear();
      for (auto& t : tok) {
        long long v;
        if (!parse_int(t, v) || v <= 0) throw fail(key + ": '" + t + "' is not a positive integer");
        out.push_back(static_cast<int>(v));
      }
    };
    auto one_int = [&](long long& out) {
      if (tok.size() != 1 || !parse_int(tok[0], out) || out < 0)
        throw fail(key + " needs one non-negative integer");
    };
    if (key == "VERSION") {
    } else if (key == "FIELDS" || key == "COLUMNS") {
      h.names = tok;
    } else if (key == "SIZE") {
      ints(h.sizes);
    } else if (key == "TYPE") {
      h.types.clear();
      for (auto& t : tok) {
        if (t.size() != 1 || (t[0] != 'F' && t[0] != 'U' && t[0] != 'I'))
          throw fail("TYPE '" + t + "' must be F, U or I");
        h.types.push_back(t[0]);
      }
    } else if (key == "COUNT") {
      ints(h.counts);
    } else if (key == "WIDTH") {
      one_int(h.width);
    } else if (key == "HEIGHT") {
      one_int(h.height);
    } else if (key == "POINTS") {
      one_int(h.points);
    } else if (key == "VIEWPOINT") {
      d.viewpoint = parse_viewpoint(tok, fail);
      d.viewpoint_identity = d.viewpoint.matrix().isIdentity(1e-12);
    } else if (key == "DATA") {
      if (tok.size() != 1 || (tok[0] != "ascii" && tok[0] != "binary" && tok[0] != "binary_compressed"))
        throw fail("DATA must be ascii, binary or binary_compressed");
      d.encoding = tok[0];
      break;
    } else {
      // A file that is not a PCD at all: say so, without its bytes on the terminal.
      const std::string shown = escaped(key.substr(0, 24));
      const bool binary = shown != key.substr(0, 24);
      throw fail(binary ? "not a PCD file (binary data where the header should be)"
                        : "unknown PCD header keyword '" + shown + "'");
    }
  }
  return h;
}

// Checks the header's fields and counts against one another and lays the
// fields out in d (offsets within a point). Returns the bytes per point.
size_t lay_out_fields(const std::string& path, PcdHeader& h, PcdData& d) {
  auto fail = [&](const std::string& what) { return failure(path, h.lines, what); };
  if (h.names.empty()) throw fail("no FIELDS in the header");
  if (h.counts.empty()) h.counts.assign(h.names.size(), 1);
  if (h.sizes.size() != h.names.size() || h.types.size() != h.names.size() || h.counts.size() != h.names.size())
    throw fail("FIELDS, SIZE, TYPE and COUNT must have the same number of entries");
  if (h.width < 0) throw fail("no WIDTH in the header");
  if (h.height < 0) h.height = 1;
  // Points are indexed by uint32 (the contract's `index`); larger counts are
  // a corrupt header, and checking here keeps WIDTH*HEIGHT from overflowing.
  constexpr long long kMaxPoints = 0xFFFFFFFFll;
  if (h.width > kMaxPoints || h.height > kMaxPoints || (h.height > 0 && h.width > kMaxPoints / h.height) ||
      h.points > kMaxPoints)
    throw fail("WIDTH " + std::to_string(h.width) + " x HEIGHT " + std::to_string(h.height) +
               (h.points >= 0 ? " (POINTS " + std::to_string(h.points) + ")" : std::string()) +
               " exceeds 4294967295 points: a corrupt header");
  if (h.points < 0) h.points = h.width * h.height;
  if (h.points != h.width * h.height)
    throw fail("POINTS " + std::to_string(h.points) + " != WIDTH*HEIGHT " + std::to_string(h.width * h.height));
  d.points = static_cast<size_t>(h.points);
  d.fields.clear();
  size_t stride = 0;
  for (size_t f = 0; f < h.names.size(); ++f) {
    PcdField fd{h.names[f], h.sizes[f], h.types[f], h.counts[f], stride};
    const bool ok = fd.type == 'F' ? (fd.size == 4 || fd.size == 8)
                                   : (fd.size == 1 || fd.size == 2 || fd.size == 4 || fd.size == 8);
    if (!ok) throw fail("field '" + fd.name + "': unsupported SIZE " + std::to_string(fd.size) + " for TYPE " + fd.type);
    stride += size_t(fd.size) * fd.count;
    if (stride > (size_t(1) << 20)) throw fail("more than 1 MiB per point (SIZE x COUNT): a corrupt header");
    d.fields.push_back(fd);
  }
  return stride;
}

// Binary: fields interleaved, one point after another.
void map_binary(const std::string& path, const uint8_t* payload, size_t payload_size, size_t stride, PcdData& d) {
  const size_t n = d.points;
  if (payload_size < n * stride)
    throw Error(path + ": truncated binary data (" + std::to_string(payload_size) + " bytes, need " +
                std::to_string(n * stride) + ")");
  // Rows past POINTS mean a wrong header, as in ascii; one closing newline is no row.
  const size_t extra = payload_size - n * stride;
  if (extra > 0 && !(extra == 1 && payload[n * stride] == '\n'))
    throw Error(path + ": " + std::to_string(extra) + " bytes of binary data after the " + std::to_string(n) +
                " points POINTS says (" + std::to_string(stride) + " bytes each): is POINTS or a SIZE wrong?");
  for (size_t f = 0; f < d.fields.size(); ++f) {
    d.base[f] = payload + d.fields[f].offset;
    d.step[f] = stride;
  }
}

// binary_compressed: LZF, then one block per field.
void decompress(const std::string& path, const uint8_t* payload, size_t payload_size, size_t stride, PcdData& d) {
  const size_t n = d.points;
  if (payload_size < 8) throw Error(path + ": truncated binary_compressed data (no size words)");
  uint32_t csize, usize;
  std::memcpy(&csize, payload, 4);
  std::memcpy(&usize, payload + 4, 4);
  if (usize != n * stride)
    throw Error(path + ": binary_compressed payload holds " + std::to_string(usize) + " bytes, expected " +
                std::to_string(n * stride));
  if (payload_size - 8 < csize) throw Error(path + ": truncated binary_compressed data");
  // LZF turns at most 3 bytes into 264 (a back-reference): a size word
  // promising more is corrupt, and must not reserve gigabytes.
  if (uint64_t(usize) > 90 * (uint64_t(csize) + 1))
    throw Error(path + ": binary_compressed data of " + std::to_string(csize) + " bytes cannot expand to " +
                std::to_string(usize) + ": corrupt size words");
  d.decompressed.resize(usize);
  if (usize > 0 && !lzf::decompress(payload + 8, csize, d.decompressed.data(), usize))
    throw Error(path + ": corrupt binary_compressed data (LZF stream does not decode)");
  // Decompressed layout is one block per field (structure of arrays).
  size_t off = 0;
  for (size_t f = 0; f < d.fields.size(); ++f) {
    const size_t width_f = size_t(d.fields[f].size) * d.fields[f].count;
    d.base[f] = d.decompressed.data() + off;
    d.step[f] = width_f;
    off += width_f * n;
  }
}

// ascii: one row of numbers per point; blank lines skipped. `line_no`: the
// header's last line.
void parse_ascii(const std::string& path, const char* p, const char* end, int line_no, PcdData& d) {
  const size_t n = d.points;
  const size_t payload_size = size_t(end - p);
  auto fail = [&](const std::string& what) { return failure(path, line_no, what); };
  d.row_values = 0;
  d.ascii_column.clear();
  for (auto& fd : d.fields) {
    d.ascii_column.push_back(d.row_values);
    d.row_values += fd.count;
  }
  // Every value takes at least a byte: a header promising far more rows
  // than the file can hold is refused before memory is reserved for them.
  if (payload_size + 1 < n * d.row_values)
    throw Error(path + ": " + std::to_string(payload_size) + " bytes of ascii data cannot hold POINTS " +
                std::to_string(n) + " (" + std::to_string(d.row_values) + " values each)");
  d.ascii.resize(n * d.row_values);
  size_t row = 0;
  while (p < end) {
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
    if (!eol) eol = end;
    ++line_no;
    size_t k = 0;
    const char* q = p;
    bool blank = true;
    while (q < eol) {
      while (q < eol && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
      if (q >= eol) break;
      blank = false;
      const char* tok_end = q;
      while (tok_end < eol && *tok_end != ' ' && *tok_end != '\t' && *tok_end != '\r') ++tok_end;
      if (row >= n) throw fail("more data rows than POINTS " + std::to_string(n));
      if (k >= d.row_values)
        throw fail("expected " + std::to_string(d.row_values) + " values, got more");
      double v;
      if (!parse_double(std::string(q, tok_end), v))
        throw fail("'" + std::string(q, tok_end) + "' is not a number");
      d.ascii[row * d.row_values + k++] = v;
      q = tok_end;
    }
    if (!blank) {
      if (k != d.row_values)
        throw fail("expected " + std::to_string(d.row_values) + " values, got " + std::to_string(k));
      ++row;
    }
    p = eol + 1;
  }
  if (row != n) throw Error(path + ": " + std::to_string(row) + " data rows, POINTS says " + std::to_string(n));
}

}  // namespace

void load_pcd(const std::string& path, PcdData& d) {
  d.file_bytes = read_whole_file(path);
  PcdHeader h = parse_header(path, d);
  const size_t stride = lay_out_fields(path, h, d);
  const std::string& bytes = d.file_bytes;
  const uint8_t* payload = reinterpret_cast<const uint8_t*>(bytes.data()) + h.payload;
  const size_t payload_size = bytes.size() - h.payload;
  d.base.assign(d.fields.size(), nullptr);
  d.step.assign(d.fields.size(), 0);
  if (d.encoding == "binary") map_binary(path, payload, payload_size, stride, d);
  else if (d.encoding == "binary_compressed") decompress(path, payload, payload_size, stride, d);
  else parse_ascii(path, bytes.data() + h.payload, bytes.data() + bytes.size(), h.lines, d);
}

}  // namespace detail

std::optional<Eigen::Isometry3d> read_pcd_viewpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open");
  // A PCD header is a few short lines ending with DATA; a file whose first
  // 64 KiB hold no DATA line is no PCD (load_pcd says the same of it).
  constexpr std::streamsize kHeaderBytes = 64 * 1024;
  std::optional<Eigen::Isometry3d> viewpoint;
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what) { return Error(path + ":" + std::to_string(line_no) + ": " + what); };
  while (std::getline(in, line)) {
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::vector<std::string> tok = detail::split_ws(line);
    if (!tok.empty() && tok[0] == "DATA") return viewpoint;
    if (!tok.empty() && tok[0] == "VIEWPOINT") {
      tok.erase(tok.begin());
      const Eigen::Isometry3d t = detail::parse_viewpoint(tok, fail);
      viewpoint = t.matrix().isIdentity(1e-12) ? std::nullopt : std::optional<Eigen::Isometry3d>(t);
    }
    if (in.tellg() > kHeaderBytes) break;
  }
  throw Error(path + ": not a PCD file (no DATA line in the header)");
}

int PcdTable::column(const std::string& name) const {
  for (size_t c = 0; c < names.size(); ++c)
    if (names[c] == name) return static_cast<int>(c);
  return -1;
}

PcdTable read_pcd_table(const std::string& path) {
  detail::PcdData d;
  detail::load_pcd(path, d);
  PcdTable t;
  t.size = d.points;
  for (size_t f = 0; f < d.fields.size(); ++f) {
    const auto& fd = d.fields[f];
    if (fd.name == "_") continue;  // padding
    for (int e = 0; e < fd.count; ++e) {
      t.names.push_back(fd.count == 1 ? fd.name : fd.name + "_" + std::to_string(e));
      t.types.push_back(fd.type);
      std::vector<double> col(d.points);
      for (size_t i = 0; i < d.points; ++i) col[i] = d.value(int(f), i, e);
      t.values.push_back(std::move(col));
    }
  }
  return t;
}

}  // namespace lista::io
