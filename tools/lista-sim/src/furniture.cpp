#include "furniture.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace lista::sim {
namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::string where(const std::string& path, int line) { return path + ":" + std::to_string(line); }

float parse_float(const std::string& text, const std::string& path, int line) {
  float v = 0.f;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || ptr != end) throw Error(where(path, line) + ": '" + text + "' is not a number");
  return v;
}

// Splits "key#N" into key and N; false when the key has no entry number.
bool split_key(const std::string& key, std::string& name, int& number) {
  const size_t hash = key.rfind('#');
  if (hash == std::string::npos || hash + 1 >= key.size() || key.size() - hash > 10) return false;
  for (size_t i = hash + 1; i < key.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(key[i]))) return false;
  name = key.substr(0, hash);
  number = std::stoi(key.substr(hash + 1));
  return true;
}

// A vertex reference of an OBJ face ("7", "7/2", "7//3", "-1/..."), 0-based.
int vertex_ref(const std::string& token, int vertex_count, const std::string& path, int line) {
  const std::string head = token.substr(0, token.find('/'));
  int v = 0;
  auto [ptr, ec] = std::from_chars(head.data(), head.data() + head.size(), v);
  if (ec != std::errc() || ptr != head.data() + head.size() || v == 0)
    throw Error(where(path, line) + ": bad face vertex '" + token + "'");
  const int index = v > 0 ? v - 1 : vertex_count + v;
  if (index < 0 || index >= vertex_count)
    throw Error(where(path, line) + ": face vertex " + std::to_string(v) + " does not exist (" +
                std::to_string(vertex_count) + " vertices so far)");
  return index;
}

std::string slug(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? char(std::tolower(c)) : '_';
  return out;
}

}  // namespace

std::vector<CatalogEntry> read_catalog(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot read the furniture catalogue");
  const fs::path folder = fs::path(path).parent_path();
  std::map<int, CatalogEntry> entries;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    text = trim(text);
    if (text.empty() || text[0] == '#' || text[0] == '!') continue;
    const size_t eq = text.find('=');
    if (eq == std::string::npos) continue;
    std::string name;
    int number = 0;
    if (!split_key(trim(text.substr(0, eq)), name, number)) continue;
    const std::string value = trim(text.substr(eq + 1));
    CatalogEntry& e = entries[number];
    if (name == "id") e.id = value;
    else if (name == "name") e.name = value;
    else if (name == "category") e.category = value;
    else if (name == "model") e.model = (folder / fs::path(value).relative_path()).string();
    else if (name == "width") e.size_cm.x() = parse_float(value, path, line);
    else if (name == "depth") e.size_cm.y() = parse_float(value, path, line);
    else if (name == "height") e.size_cm.z() = parse_float(value, path, line);
    else if (name == "doorOrWindow") e.door_or_window = value == "true";
    else if (name == "staircaseCutOutShape") e.staircase = true;
    else if (name == "modelRotation") {
      std::istringstream ss(value);
      std::string t;
      for (int k = 0; k < 9; ++k) {
        if (!(ss >> t)) throw Error(where(path, line) + ": modelRotation needs 9 numbers");
        e.rotation(k / 3, k % 3) = parse_float(t, path, line);
      }
    }
  }
  std::vector<CatalogEntry> out;
  for (auto& [number, e] : entries)
    if (!e.model.empty()) out.push_back(std::move(e));
  return out;
}

TriMesh read_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot read the OBJ file");
  TriMesh mesh;
  std::string text, tag;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.size() < 2 || (text[0] != 'v' && text[0] != 'f') || !std::isspace(static_cast<unsigned char>(text[1])))
      continue;  // vt, vn, g, o, usemtl, comments ...
    std::istringstream ss(text);
    ss >> tag;
    if (tag == "v") {
      std::string x, y, z;
      if (!(ss >> x >> y >> z)) throw Error(where(path, line) + ": a vertex needs three coordinates");
      mesh.vertices.emplace_back(parse_float(x, path, line), parse_float(y, path, line), parse_float(z, path, line));
    } else {
      std::vector<int> face;
      std::string token;
      while (ss >> token) face.push_back(vertex_ref(token, int(mesh.vertices.size()), path, line));
      // Exporters write the odd two-vertex "face" (an edge): it has no area.
      for (size_t k = 1; k + 1 < face.size(); ++k) mesh.triangles.emplace_back(face[0], face[k], face[k + 1]);
    }
  }
  if (mesh.triangles.empty()) throw Error(path + ": no faces");
  return mesh;
}

Shape furniture_shape(const CatalogEntry& e) {
  Shape s;
  s.mesh = read_obj(e.model);
  // SH3D: x right, y up, z towards the viewer (depth); ours: z up.
  for (auto& v : s.mesh.vertices) {
    const Eigen::Vector3f r = e.rotation * v;
    v = Eigen::Vector3f(r.x(), -r.z(), r.y());
  }
  Eigen::Vector3f lo, hi;
  s.mesh.bounds(lo, hi);
  const Eigen::Vector3f extent = (hi - lo).cwiseMax(1e-6f);
  const Eigen::Vector3f scale = (e.size_cm / 100.0f).cwiseQuotient(extent);
  for (auto& v : s.mesh.vertices) v = (v - lo).cwiseProduct(scale);
  s.cls = "sh3d/" + slug(e.category.empty() ? std::string("misc") : e.category);
  s.source = "sweethome3d";
  s.id = "sh3d/" + slug(e.id.empty() ? e.name : e.id);
  s.reflectivity = 0.5f;
  normalise_shape(s);
  return s;
}

std::vector<Shape> load_furniture(const std::string& folder, std::vector<std::string>* skipped) {
  std::vector<std::string> catalogues;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file() && it->path().filename() == "PluginFurnitureCatalog.properties")
      catalogues.push_back(it->path().string());
  if (ec) throw Error(folder + ": " + ec.message() + " (run tools/fetch-shapes.sh " + folder + ")");
  if (catalogues.empty())
    throw Error(folder + ": no furniture catalogue (PluginFurnitureCatalog.properties) found; run tools/fetch-shapes.sh " +
                folder);
  std::sort(catalogues.begin(), catalogues.end());
  std::vector<Shape> out;
  for (const auto& cat : catalogues)
    for (const auto& e : read_catalog(cat)) {
      const Eigen::Vector3f m = e.size_cm / 100.0f;
      const bool person = e.category == "Characters";  // people are distractors, not objects
      if (e.door_or_window || e.staircase || person || m.z() < 0.2f || m.z() > 3.0f ||
          std::max(m.x(), m.y()) < 0.2f || m.x() > 6.0f || m.y() > 6.0f || m.minCoeff() <= 0.0f)
        continue;
      try {
        out.push_back(furniture_shape(e));
      } catch (const Error& err) {
        if (skipped) skipped->push_back(err.what());
      }
    }
  return out;
}

}  // namespace lista::sim
