// PCD reading: header parsing plus the ascii / binary / binary_compressed
// payloads, any field sizes, types and counts (padding fields included).
#include "pcd_format.hpp"
#include "lzf.hpp"
#include "text_util.hpp"

#include <cctype>
#include <lista/error.hpp>
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
inline double load_as(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
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

void load_pcd(const std::string& path, PcdData& d) {
  d.file_bytes = read_whole_file(path);
  const std::string& bytes = d.file_bytes;
  size_t pos = 0;
  int line_no = 0;
  std::vector<int> sizes, counts;
  std::vector<char> types;
  std::vector<std::string> names;
  long long width = -1, height = -1, points = -1;
  auto fail = [&](const std::string& what) -> Error {
    return Error(path + ":" + std::to_string(line_no) + ": " + what);
  };
  // Header: one keyword per line until DATA.
  while (true) {
    if (pos >= bytes.size()) throw Error(path + ": not a PCD file (no DATA line in the header)");
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = std::min(bytes.size(), eol + 1);
    ++line_no;
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
      names = tok;
    } else if (key == "SIZE") {
      ints(sizes);
    } else if (key == "TYPE") {
      types.clear();
      for (auto& t : tok) {
        if (t.size() != 1 || (t[0] != 'F' && t[0] != 'U' && t[0] != 'I'))
          throw fail("TYPE '" + t + "' must be F, U or I");
        types.push_back(t[0]);
      }
    } else if (key == "COUNT") {
      ints(counts);
    } else if (key == "WIDTH") {
      one_int(width);
    } else if (key == "HEIGHT") {
      one_int(height);
    } else if (key == "POINTS") {
      one_int(points);
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
  if (names.empty()) throw fail("no FIELDS in the header");
  if (counts.empty()) counts.assign(names.size(), 1);
  if (sizes.size() != names.size() || types.size() != names.size() || counts.size() != names.size())
    throw fail("FIELDS, SIZE, TYPE and COUNT must have the same number of entries");
  if (width < 0) throw fail("no WIDTH in the header");
  if (height < 0) height = 1;
  // Points are indexed by uint32 (the contract's `index`); larger counts are
  // a corrupt header, and checking here keeps WIDTH*HEIGHT from overflowing.
  constexpr long long kMaxPoints = 0xFFFFFFFFll;
  if (width > kMaxPoints || height > kMaxPoints || (height > 0 && width > kMaxPoints / height) ||
      points > kMaxPoints)
    throw fail("WIDTH " + std::to_string(width) + " x HEIGHT " + std::to_string(height) +
               (points >= 0 ? " (POINTS " + std::to_string(points) + ")" : std::string()) +
               " exceeds 4294967295 points: a corrupt header");
  if (points < 0) points = width * height;
  if (points != width * height)
    throw fail("POINTS " + std::to_string(points) + " != WIDTH*HEIGHT " + std::to_string(width * height));
  d.points = static_cast<size_t>(points);
  d.fields.clear();
  size_t stride = 0;
  for (size_t f = 0; f < names.size(); ++f) {
    PcdField fd{names[f], sizes[f], types[f], counts[f], stride};
    const bool ok = fd.type == 'F' ? (fd.size == 4 || fd.size == 8)
                                   : (fd.size == 1 || fd.size == 2 || fd.size == 4 || fd.size == 8);
    if (!ok) throw fail("field '" + fd.name + "': unsupported SIZE " + std::to_string(fd.size) + " for TYPE " + fd.type);
    stride += size_t(fd.size) * fd.count;
    if (stride > (size_t(1) << 20)) throw fail("more than 1 MiB per point (SIZE x COUNT): a corrupt header");
    d.fields.push_back(fd);
  }
  const size_t n = d.points;
  const uint8_t* payload = reinterpret_cast<const uint8_t*>(bytes.data()) + pos;
  const size_t payload_size = bytes.size() - pos;
  d.base.assign(d.fields.size(), nullptr);
  d.step.assign(d.fields.size(), 0);

  if (d.encoding == "binary") {
    if (payload_size < n * stride)
      throw Error(path + ": truncated binary data (" + std::to_string(payload_size) + " bytes, need " +
                  std::to_string(n * stride) + ")");
    for (size_t f = 0; f < d.fields.size(); ++f) {
      d.base[f] = payload + d.fields[f].offset;
      d.step[f] = stride;
    }
  } else if (d.encoding == "binary_compressed") {
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
  } else {  // ascii
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
    const char* p = bytes.data() + pos;
    const char* end = bytes.data() + bytes.size();
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
