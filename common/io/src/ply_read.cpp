// PLY scans: ascii, binary_little_endian, binary_big_endian; the `vertex`
// element with x y z and optional intensity and label, any scalar types.
// Elements before `vertex` are skipped (binary: only if they have no lists).
#include "scan_format.hpp"
#include "text_util.hpp"

#include <lista/error.hpp>
#include <lista_io/byte_load.hpp>

#include <algorithm>
#include <cctype>
#include <cstring>

namespace lista::io::detail {

namespace {

struct PlyProperty {
  std::string name;
  char kind = 'f';  // f float, i signed, u unsigned
  int size = 4;
  bool list = false;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
};

bool scalar_type(const std::string& t, PlyProperty& p) {
  static const struct { const char* name; char kind; int size; } table[] = {
      {"char", 'i', 1},   {"int8", 'i', 1},   {"uchar", 'u', 1},  {"uint8", 'u', 1},
      {"short", 'i', 2},  {"int16", 'i', 2},  {"ushort", 'u', 2}, {"uint16", 'u', 2},
      {"int", 'i', 4},    {"int32", 'i', 4},  {"uint", 'u', 4},   {"uint32", 'u', 4},
      {"float", 'f', 4},  {"float32", 'f', 4}, {"double", 'f', 8}, {"float64", 'f', 8}};
  for (const auto& e : table)
    if (t == e.name) {
      p.kind = e.kind;
      p.size = e.size;
      return true;
    }
  return false;
}

double load(const uint8_t* p, const PlyProperty& prop, bool swap) {
  auto as = [&](auto v) { return static_cast<double>(load_bytes<decltype(v)>(p, swap)); };
  if (prop.kind == 'f') return prop.size == 4 ? as(float{}) : as(double{});
  if (prop.kind == 'u') {
    switch (prop.size) {
      case 1: return as(uint8_t{});
      case 2: return as(uint16_t{});
      default: return as(uint32_t{});
    }
  }
  switch (prop.size) {
    case 1: return as(int8_t{});
    case 2: return as(int16_t{});
    default: return as(int32_t{});
  }
}

bool host_little_endian() {
  const uint16_t v = 1;
  uint8_t b;
  std::memcpy(&b, &v, 1);
  return b == 1;
}

// The header: format, elements and their properties, and where the data
// starts (byte offset and the lines read so far).
struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  size_t data = 0;
  int lines = 0;
};

PlyHeader read_header(const std::string& path, const std::string& bytes) {
  PlyHeader h;
  size_t& pos = h.data;
  int& line_no = h.lines;
  auto fail = [&](const std::string& what) { return Error(path + ":" + std::to_string(line_no) + ": " + what); };
  auto next_line = [&]() {
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) throw Error(path + ": PLY header has no end_header");
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  };
  if (next_line() != "ply") throw Error(path + ": not a PLY file (first line is not 'ply')");
  std::string& format = h.format;
  std::vector<PlyElement>& elements = h.elements;
  while (true) {
    const std::vector<std::string> tok = split_ws(next_line());
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "format") {
      if (tok.size() < 2 || (tok[1] != "ascii" && tok[1] != "binary_little_endian" && tok[1] != "binary_big_endian"))
        throw fail("unknown PLY format");
      format = tok[1];
    } else if (tok[0] == "element") {
      long long count;
      if (tok.size() != 3 || !parse_int(tok[2], count) || count < 0) throw fail("bad element line");
      // Vertices are indexed by uint32 (the contract's `index`); more items
      // in any element is a corrupt header, whose sizes would overflow.
      if (count > 0xFFFFFFFFll)
        throw fail("element '" + tok[1] + "' has " + tok[2] + " items, more than 4294967295: a corrupt header");
      elements.push_back({tok[1], size_t(count), {}});
    } else if (tok[0] == "property") {
      if (elements.empty()) throw fail("property before any element");
      PlyProperty p;
      if (tok.size() == 5 && tok[1] == "list") {
        p.list = true;
        p.name = tok[4];
      } else if (tok.size() == 3) {
        if (!scalar_type(tok[1], p)) throw fail("unknown property type '" + tok[1] + "'");
        p.name = tok[2];
      } else {
        throw fail("bad property line");
      }
      elements.back().props.push_back(p);
    } else {
      throw fail("unknown PLY header keyword '" + tok[0] + "'");
    }
  }
  if (format.empty()) throw Error(path + ": PLY header has no format line");
  return h;
}

// Which vertex properties hold x, y, z, the intensity and the label (-1: none).
struct VertexColumns {
  int x = -1, y = -1, z = -1, intensity = -1, label = -1;
};

VertexColumns vertex_columns(const std::string& path, const PlyElement& v) {
  int ix = -1, iy = -1, iz = -1, ii = -1, il = -1;
  size_t intensity_rank = kIntensityNames.size();  // the best name found so far (scan_format.hpp)
  for (size_t k = 0; k < v.props.size(); ++k) {
    if (v.props[k].list) throw Error(path + ": list property '" + v.props[k].name + "' in vertex element");
    std::string n = v.props[k].name;  // case-insensitive: PDAL and CloudCompare write "X", "Intensity"
    std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    const size_t rank = size_t(std::find(kIntensityNames.begin(), kIntensityNames.end(), n) - kIntensityNames.begin());
    if (n == "x" && ix < 0) ix = int(k);
    else if (n == "y" && iy < 0) iy = int(k);
    else if (n == "z" && iz < 0) iz = int(k);
    else if (rank < intensity_rank) ii = int(k), intensity_rank = rank;
    else if (n == "label" && il < 0) il = int(k);
  }
  if (ix < 0 || iy < 0 || iz < 0) throw Error(path + ": PLY vertex element lacks one of x, y, z");
  return {ix, iy, iz, ii, il};
}

// ascii: one line per item, the elements before vertex skipped. `emit(i)`
// takes vertex i's values from `vals`.
template <class Emit>
void read_ascii_vertices(const std::string& path, const std::string& bytes, const PlyHeader& h, size_t vi,
                         std::vector<double>& vals, const Emit& emit) {
  const PlyElement& v = h.elements[vi];
  const std::vector<PlyElement>& elements = h.elements;
  size_t pos = h.data;
  int line_no = h.lines;
  auto fail = [&](const std::string& what) { return Error(path + ":" + std::to_string(line_no) + ": " + what); };
  // Skip the lines of elements before vertex (one line per item).
  size_t skip = 0;
  for (size_t e = 0; e < vi; ++e) skip += elements[e].count;
  size_t i = 0;
  while (i < v.count) {
    if (pos >= bytes.size()) throw Error(path + ": only " + std::to_string(i) + " of " + std::to_string(v.count) + " vertices");
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    const std::vector<std::string> tok = split_ws(bytes.substr(pos, eol - pos));
    pos = eol + 1;
    ++line_no;
    if (tok.empty()) continue;
    if (skip > 0) {
      --skip;
      continue;
    }
    if (tok.size() != v.props.size())
      throw fail("expected " + std::to_string(v.props.size()) + " values, got " + std::to_string(tok.size()));
    for (size_t k = 0; k < tok.size(); ++k)
      if (!parse_double(tok[k], vals[k])) throw fail("'" + tok[k] + "' is not a number");
    emit(i++);
  }
  // Rows past the count mean a wrong header, unless other elements follow.
  if (vi + 1 < elements.size()) return;
  while (pos < bytes.size()) {
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    ++line_no;
    if (!split_ws(bytes.substr(pos, eol - pos)).empty())
      throw fail("more data rows than 'element vertex " + std::to_string(v.count) + "'");
    pos = eol + 1;
  }
}

// binary: fixed-size rows; the elements before vertex skipped (they may not
// hold lists).
template <class Emit>
void read_binary_vertices(const std::string& path, const std::string& bytes, const PlyHeader& h, size_t vi,
                          std::vector<double>& vals, const Emit& emit) {
  const PlyElement& v = h.elements[vi];
  const std::vector<PlyElement>& elements = h.elements;
  const std::string& format = h.format;
  const size_t pos = h.data;
  const bool swap = (format == "binary_little_endian") != host_little_endian();
  size_t offset = pos;
  for (size_t e = 0; e < vi; ++e) {
    size_t row = 0;
    for (const auto& p : elements[e].props) {
      if (p.list) throw Error(path + ": cannot skip list element '" + elements[e].name + "' before vertex");
      row += size_t(p.size);
    }
    offset += row * elements[e].count;
  }
  size_t row = 0;
  std::vector<size_t> at;
  for (const auto& p : v.props) {
    at.push_back(row);
    row += size_t(p.size);
  }
  if (offset > bytes.size() || bytes.size() - offset < row * v.count)
    throw Error(path + ": truncated binary PLY data");
  const uint8_t* base = reinterpret_cast<const uint8_t*>(bytes.data()) + offset;
  // Bytes past the last element mean a wrong count; one closing newline is no row.
  const size_t extra = bytes.size() - offset - row * v.count;
  if (vi + 1 == elements.size() && extra > 0 && !(extra == 1 && bytes.back() == '\n'))
    throw Error(path + ": " + std::to_string(extra) + " bytes of binary data after the " + std::to_string(v.count) +
                " vertices 'element vertex' says: is the count wrong?");
  for (size_t i = 0; i < v.count; ++i) {
    for (size_t k = 0; k < v.props.size(); ++k) vals[k] = load(base + i * row + at[k], v.props[k], swap);
    emit(i);
  }
}

}  // namespace

ScanFile read_ply(const std::string& path, uint32_t scan_id) {
  const std::string bytes = read_whole_file(path);
  const PlyHeader h = read_header(path, bytes);
  size_t vi = 0;
  while (vi < h.elements.size() && h.elements[vi].name != "vertex") ++vi;
  if (vi == h.elements.size()) throw Error(path + ": PLY file has no vertex element");
  const PlyElement& v = h.elements[vi];
  const VertexColumns col = vertex_columns(path, v);
  ScanFile s;
  s.points_in_file = static_cast<uint32_t>(v.count);
  // Reserve only what the file can hold (at least 2 bytes a vertex): a
  // header's count alone must not reserve gigabytes.
  s.points.reserve(std::min<size_t>(v.count, (bytes.size() - h.data) / 2 + 1));
  std::vector<double> vals(v.props.size());
  auto emit = [&](size_t i) {
    detail::add_point(s, scan_id, uint32_t(i), float(vals[col.x]), float(vals[col.y]), float(vals[col.z]),
                      col.intensity >= 0, col.intensity >= 0 ? float(vals[col.intensity]) : 0.f, col.label >= 0,
                      col.label >= 0 ? detail::to_label(vals[col.label], s) : 0u);
  };
  if (h.format == "ascii") read_ascii_vertices(path, bytes, h, vi, vals, emit);
  else read_binary_vertices(path, bytes, h, vi, vals, emit);
  return s;
}

}  // namespace lista::io::detail
