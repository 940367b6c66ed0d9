// PCD writing in the three encodings, atomically (temp file, then rename).
#include "lzf.hpp"

#include <lista/error.hpp>
#include <lista_io/atomic_file.hpp>
#include <lista_io/pcd.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace lista::io {

namespace {

void check_columns(const std::string& path, const std::vector<PcdColumn>& columns, size_t n) {
  if (columns.empty()) throw Error(path + ": no columns to write");
  for (const auto& c : columns) {
    if (c.type != 'F' && c.type != 'U' && c.type != 'I')
      throw Error(path + ": column '" + c.name + "' has type '" + c.type + "', expected F, U or I");
    if (n > 0 && !c.data) throw Error(path + ": column '" + c.name + "' has no data");
    if (c.name.empty() || c.name.find_first_of(" \t\n") != std::string::npos)
      throw Error(path + ": bad column name '" + c.name + "'");
  }
}

std::string header(size_t n, const std::vector<PcdColumn>& columns, PcdEncoding enc,
                   const Eigen::Isometry3d& vp) {
  std::string fields, sizes, types, counts;
  for (const auto& c : columns) {
    fields += " " + c.name;
    sizes += " 4";
    types += std::string(" ") + c.type;
    counts += " 1";
  }
  const Eigen::Quaterniond q(vp.rotation());
  const Eigen::Vector3d t = vp.translation();
  char vpbuf[256];
  std::snprintf(vpbuf, sizeof vpbuf, "VIEWPOINT %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", t.x(), t.y(),
                t.z(), q.w(), q.x(), q.y(), q.z());
  const char* data = enc == PcdEncoding::ascii ? "ascii" : enc == PcdEncoding::binary ? "binary" : "binary_compressed";
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS" + fields + "\nSIZE" + sizes +
         "\nTYPE" + types + "\nCOUNT" + counts + "\nWIDTH " + std::to_string(n) + "\nHEIGHT 1\n" + vpbuf +
         "POINTS " + std::to_string(n) + "\nDATA " + data + "\n";
}

struct FileCloser {
  void operator()(std::FILE* f) const { if (f) std::fclose(f); }
};

}  // namespace

void write_pcd(const std::string& path, size_t n, const std::vector<PcdColumn>& columns, PcdEncoding encoding,
               const Eigen::Isometry3d& viewpoint) {
  check_columns(path, columns, n);
  if (n > 0xffffffffu) throw Error(path + ": too many points for one PCD file");
  const std::string tmp = temp_name(path);
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(tmp.c_str(), "wb"));
  if (!f) throw Error(path + ": cannot write (" + std::strerror(errno) + ")");
  const std::string head = header(n, columns, encoding, viewpoint);
  bool ok = std::fwrite(head.data(), 1, head.size(), f.get()) == head.size();
  const size_t row = columns.size() * 4;
  if (encoding == PcdEncoding::ascii) {
    std::string text;
    text.reserve(n * columns.size() * 12);
    char buf[64];
    for (size_t i = 0; i < n; ++i) {
      for (size_t c = 0; c < columns.size(); ++c) {
        const uint8_t* p = static_cast<const uint8_t*>(columns[c].data) + i * 4;
        int len;
        if (columns[c].type == 'F') {
          float v;
          std::memcpy(&v, p, 4);
          len = std::snprintf(buf, sizeof buf, "%.9g", v);
        } else if (columns[c].type == 'U') {
          uint32_t v;
          std::memcpy(&v, p, 4);
          len = std::snprintf(buf, sizeof buf, "%u", v);
        } else {
          int32_t v;
          std::memcpy(&v, p, 4);
          len = std::snprintf(buf, sizeof buf, "%d", v);
        }
        if (c) text += ' ';
        text.append(buf, size_t(len));
      }
      text += '\n';
    }
    ok = ok && std::fwrite(text.data(), 1, text.size(), f.get()) == text.size();
  } else if (encoding == PcdEncoding::binary) {
    std::vector<uint8_t> buf(n * row);
    for (size_t c = 0; c < columns.size(); ++c) {
      const uint8_t* src = static_cast<const uint8_t*>(columns[c].data);
      for (size_t i = 0; i < n; ++i) std::memcpy(&buf[i * row + c * 4], src + i * 4, 4);
    }
    ok = ok && std::fwrite(buf.data(), 1, buf.size(), f.get()) == buf.size();
  } else {
    // binary_compressed: one block per column (structure of arrays), then LZF.
    std::vector<uint8_t> soa(n * row);
    for (size_t c = 0; c < columns.size(); ++c)
      if (n) std::memcpy(&soa[c * n * 4], columns[c].data, n * 4);
    std::vector<uint8_t> packed;
    packed.reserve(soa.size() / 2 + 64);
    lzf::compress(soa.data(), soa.size(), packed);
    const uint32_t sizes[2] = {static_cast<uint32_t>(packed.size()), static_cast<uint32_t>(soa.size())};
    ok = ok && std::fwrite(sizes, 4, 2, f.get()) == 2;
    ok = ok && std::fwrite(packed.data(), 1, packed.size(), f.get()) == packed.size();
  }
  ok = std::fclose(f.release()) == 0 && ok;
  if (!ok) {
    std::remove(tmp.c_str());
    throw Error(path + ": write failed (disk full?)");
  }
  commit_file(tmp, path);
}

void write_scan_pcd(const std::string& path, const PointSet& points, PcdEncoding encoding) {
  const size_t n = points.size();
  // Provenance (scan, index) is not written: a scan file's index is its row.
  if ((points.has_intensity() && points.intensity.size() != n) || (points.has_label() && points.label.size() != n))
    throw Error(path + ": intensity/label channels do not have one value per point");
  std::vector<float> x(n), y(n), z(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = points.xyz[i].x();
    y[i] = points.xyz[i].y();
    z[i] = points.xyz[i].z();
  }
  std::vector<PcdColumn> cols = {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()}};
  if (points.has_intensity()) cols.push_back({"intensity", 'F', points.intensity.data()});
  if (points.has_label()) cols.push_back({"label", 'U', points.label.data()});
  write_pcd(path, n, cols, encoding);
}

}  // namespace lista::io
