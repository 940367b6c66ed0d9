// report.json and ground_truth.json: strict reading (every required field
// checked, errors name the file and the field) and atomic writing.
#include "rotation_check.hpp"
#include "text_util.hpp"

#include <lista/error.hpp>
#include <lista_io/atomic_file.hpp>
#include <lista_io/report.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>

namespace lista::io {

using json = nlohmann::ordered_json;

namespace {

json matrix_json(const Eigen::Matrix4d& m) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return rows;
}

json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Strict accessors: `where` is "file: objects[3].centroid" style context.
struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error(file + ": " + where + ": " + what);
  }
  const json& field(const json& obj, const std::string& where, const std::string& key) const {
    if (!obj.is_object()) fail(where, "expected a JSON object");
    auto it = obj.find(key);
    if (it == obj.end()) fail(where, "missing field '" + key + "'");
    return *it;
  }
  double number(const json& v, const std::string& where) const {
    if (!v.is_number()) fail(where, "expected a number, got " + std::string(v.type_name()));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(where, "not a finite number");
    return d;
  }
  int integer(const json& v, const std::string& where) const {
    if (!v.is_number_integer()) fail(where, "expected an integer, got " + std::string(v.type_name()));
    const int64_t i = v.get<int64_t>();
    if (i < INT32_MIN || i > INT32_MAX) fail(where, std::to_string(i) + " is out of range (32-bit)");
    return int(i);
  }
  // A rigid transform: last row 0 0 0 1, rotation orthonormal and proper. An
  // all-zero or scaled matrix would otherwise be scored as if it were a pose.
  Eigen::Matrix4d rigid(const json& v, const std::string& where) const {
    const Eigen::Matrix4d m = matrix(v, where);
    if (!m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1), 1e-6))
      fail(where, "is not a rigid transform (its last row must be 0 0 0 1)");
    if (const std::string why = detail::rotation_problem(m.topLeftCorner<3, 3>()); !why.empty())
      fail(where, "is not a rigid transform: " + why);
    return m;
  }
  std::string text(const json& v, const std::string& where) const {
    if (!v.is_string()) fail(where, "expected a string, got " + std::string(v.type_name()));
    return v.get<std::string>();
  }
  Eigen::Vector3d vec3(const json& v, const std::string& where) const {
    if (!v.is_array() || v.size() != 3) fail(where, "expected [x, y, z]");
    return Eigen::Vector3d(number(v[0], where), number(v[1], where), number(v[2], where));
  }
  Eigen::Matrix4d matrix(const json& v, const std::string& where) const {
    if (!v.is_array() || v.size() != 4) fail(where, "expected a 4x4 matrix (4 rows of 4 numbers)");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      if (!v[r].is_array() || v[r].size() != 4) fail(where, "expected a 4x4 matrix (4 rows of 4 numbers)");
      for (int c = 0; c < 4; ++c) m(r, c) = number(v[r][c], where);
    }
    return m;
  }
  std::vector<std::string> names(const json& v, const std::string& where) const {
    if (!v.is_array()) fail(where, "expected a list of names");
    std::vector<std::string> out;
    for (size_t i = 0; i < v.size(); ++i) out.push_back(text(v[i], where + "[" + std::to_string(i) + "]"));
    return out;
  }
  // The file's top-level object, its "format" checked.
  json parse(const std::string& expected_format) const {
    json root;
    try {
      root = json::parse(detail::read_whole_file(file));
    } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers like 1e999
      throw Error(file + ": invalid JSON (" + std::string(e.what()) + ")");
    }
    if (!root.is_object()) fail("top level", "expected a JSON object");
    const std::string f = text(field(root, "top level", "format"), "format");
    if (f != expected_format) fail("format", "is '" + f + "', expected '" + expected_format + "'");
    return root;
  }
  // Every mission of the list has a matrix in `key`, and no other.
  std::map<std::string, Eigen::Matrix4d> per_mission(const json& root, const std::string& key,
                                                     const std::vector<std::string>& missions) const {
    const json& obj = field(root, "top level", key);
    if (!obj.is_object()) fail(key, "expected an object keyed by mission name");
    std::map<std::string, Eigen::Matrix4d> out;
    for (const auto& m : missions) {
      if (!obj.contains(m)) fail(key, "no entry for mission '" + m + "'");
      out[m] = rigid(obj[m], key + "." + m);
    }
    for (auto it = obj.begin(); it != obj.end(); ++it)
      if (!out.count(it.key())) fail(key, "unknown mission '" + it.key() + "'");
    return out;
  }
};

void check_mission(const Reader& rd, const std::vector<std::string>& missions, const std::string& m,
                   const std::string& where) {
  if (std::find(missions.begin(), missions.end(), m) == missions.end())
    rd.fail(where, "unknown mission '" + m + "' (not in \"missions\")");
}

}  // namespace

void write_report(const std::string& path, const Report& report) {
  json root;
  root["format"] = report.format;
  root["missions"] = report.missions;
  json align = json::object();
  for (const auto& m : report.missions) {
    auto it = report.alignment.find(m);
    align[m] = matrix_json(it == report.alignment.end() ? Eigen::Matrix4d::Identity() : it->second);
  }
  root["alignment"] = align;
  json objects = json::array();
  for (const auto& o : report.objects) {
    json j;
    j["id"] = o.id;
    j["mission"] = o.mission;
    j["status"] = o.status;
    j["centroid"] = vec_json(o.centroid);
    j["bbox_min"] = vec_json(o.bbox_min);
    j["bbox_max"] = vec_json(o.bbox_max);
    j["points"] = o.points;
    j["group"] = o.group;
    j["confidence"] = o.confidence;
    j["match"] = o.match >= 0 ? json(o.match) : json(nullptr);
    if (o.transform) {
      j["transform"] = matrix_json(*o.transform);
      json alternatives = json::array();
      for (const auto& a : o.alternative_transforms) alternatives.push_back(matrix_json(a));
      j["alternative_transforms"] = std::move(alternatives);
    }
    j["history"] = o.history;
    j["floor_z"] = o.floor_z ? json(*o.floor_z) : json(nullptr);
    objects.push_back(std::move(j));
  }
  root["objects"] = std::move(objects);
  json timings = json::object();
  for (const auto& [stage, s] : report.timings_s) timings[stage] = s;
  root["timings_s"] = timings;
  json extra;
  try {
    extra = json::parse(report.extra_json.empty() ? "{}" : report.extra_json);
  } catch (const json::parse_error& e) {
    throw Error(path + ": extra report fields are not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!extra.is_object()) throw Error(path + ": extra report fields must be a JSON object");
  for (auto it = extra.begin(); it != extra.end(); ++it) {
    if (root.contains(it.key())) throw Error(path + ": extra field '" + it.key() + "' clashes with a contract field");
    root[it.key()] = it.value();
  }
  // A path that is not UTF-8 (a folder named in Latin-1) is written with U+FFFD, not an exception.
  write_file_atomic(path, root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

Report read_report(const std::string& path) {
  Reader rd{path};
  const json root = rd.parse("lista-report/1");
  Report r;
  r.missions = rd.names(rd.field(root, "top level", "missions"), "missions");
  r.alignment = rd.per_mission(root, "alignment", r.missions);
  const json& objs = rd.field(root, "top level", "objects");
  if (!objs.is_array()) rd.fail("objects", "expected a list");
  std::set<int> ids;
  for (size_t i = 0; i < objs.size(); ++i) {
    const std::string w = "objects[" + std::to_string(i) + "]";
    const json& j = objs[i];
    ReportObject o;
    o.id = rd.integer(rd.field(j, w, "id"), w + ".id");
    if (!ids.insert(o.id).second) rd.fail(w + ".id", "duplicate id " + std::to_string(o.id));
    o.mission = rd.text(rd.field(j, w, "mission"), w + ".mission");
    check_mission(rd, r.missions, o.mission, w + ".mission");
    o.status = rd.text(rd.field(j, w, "status"), w + ".status");
    if (o.status != "moved" && o.status != "removed" && o.status != "added")
      rd.fail(w + ".status", "is '" + o.status + "', expected moved, removed or added");
    o.centroid = rd.vec3(rd.field(j, w, "centroid"), w + ".centroid");
    o.bbox_min = rd.vec3(rd.field(j, w, "bbox_min"), w + ".bbox_min");
    o.bbox_max = rd.vec3(rd.field(j, w, "bbox_max"), w + ".bbox_max");
    const json& pts = rd.field(j, w, "points");
    if (!pts.is_number_integer() || pts.get<int64_t>() < 0 || pts.get<int64_t>() > int64_t(UINT32_MAX))
      rd.fail(w + ".points", "must be an integer in [0, 4294967295]");
    o.points = size_t(pts.get<int64_t>());
    o.group = rd.integer(rd.field(j, w, "group"), w + ".group");
    o.confidence = rd.number(rd.field(j, w, "confidence"), w + ".confidence");
    if (o.confidence < 0 || o.confidence > 1) rd.fail(w + ".confidence", "must be in [0, 1]");
    const json& match = rd.field(j, w, "match");
    o.match = match.is_null() ? -1 : rd.integer(match, w + ".match");
    // The contract gives transforms for moved objects; null elsewhere is the same as none.
    if (j.contains("transform") && !j["transform"].is_null()) o.transform = rd.rigid(j["transform"], w + ".transform");
    if (o.status == "moved" && !o.transform) rd.fail(w, "moved object has no 'transform'");
    if (j.contains("alternative_transforms")) {
      const json& alts = j["alternative_transforms"];
      const std::string wa = w + ".alternative_transforms";
      if (!alts.is_array()) rd.fail(wa, "expected a list of 4x4 transforms");
      for (size_t k = 0; k < alts.size(); ++k)
        o.alternative_transforms.push_back(rd.rigid(alts[k], wa + "[" + std::to_string(k) + "]"));
    }
    if (j.contains("history")) {
      const json& h = j["history"];
      if (!h.is_array()) rd.fail(w + ".history", "expected a list of ids");
      for (size_t k = 0; k < h.size(); ++k) o.history.push_back(rd.integer(h[k], w + ".history"));
    }
    if (j.contains("floor_z") && !j["floor_z"].is_null()) o.floor_z = rd.number(j["floor_z"], w + ".floor_z");
    r.objects.push_back(std::move(o));
  }
  std::map<int, const ReportObject*> by_id;
  for (const auto& o : r.objects) by_id[o.id] = &o;
  for (const auto& o : r.objects) {
    if (o.match < 0) continue;
    const std::string w = "objects (id " + std::to_string(o.id) + ").match";
    if (!ids.count(o.match)) rd.fail(w, "names no object id " + std::to_string(o.match));
    if (o.match == o.id) rd.fail(w, "names the object itself");
    if (by_id.at(o.match)->mission == o.mission)
      rd.fail(w, "names object " + std::to_string(o.match) + " of the same mission '" + o.mission +
                     "'; a match is the same object in another mission");
  }
  const json& timings = rd.field(root, "top level", "timings_s");
  if (!timings.is_object()) rd.fail("timings_s", "expected an object of stage id -> seconds");
  for (auto it = timings.begin(); it != timings.end(); ++it)
    r.timings_s.emplace_back(it.key(), rd.number(it.value(), "timings_s." + it.key()));
  json extra = json::object();
  for (auto it = root.begin(); it != root.end(); ++it) {
    static const std::set<std::string> known = {"format", "missions", "alignment", "objects", "timings_s"};
    if (!known.count(it.key())) extra[it.key()] = it.value();
  }
  r.extra_json = extra.dump();
  return r;
}

void write_ground_truth(const std::string& path, const GroundTruth& truth) {
  json root;
  root["format"] = truth.format;
  root["missions"] = truth.missions;
  json m2w = json::object();
  for (const auto& m : truth.missions) {
    auto it = truth.mission_to_world.find(m);
    m2w[m] = matrix_json(it == truth.mission_to_world.end() ? Eigen::Matrix4d::Identity() : it->second);
  }
  root["mission_to_world"] = m2w;
  json objects = json::array();
  for (const auto& o : truth.objects) {
    json j;
    j["id"] = o.id;
    j["class"] = o.class_name;
    j["dynamic"] = o.dynamic;
    json poses = json::object();
    for (const auto& m : truth.missions) {
      auto it = o.poses.find(m);
      poses[m] = (it == o.poses.end() || !it->second) ? json(nullptr) : matrix_json(*it->second);
    }
    j["poses"] = poses;
    objects.push_back(std::move(j));
  }
  root["objects"] = std::move(objects);
  // A path that is not UTF-8 (a folder named in Latin-1) is written with U+FFFD, not an exception.
  write_file_atomic(path, root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

GroundTruth read_ground_truth(const std::string& path) {
  Reader rd{path};
  const json root = rd.parse("lista-ground-truth/1");
  GroundTruth g;
  g.missions = rd.names(rd.field(root, "top level", "missions"), "missions");
  g.mission_to_world = rd.per_mission(root, "mission_to_world", g.missions);
  const json& objs = rd.field(root, "top level", "objects");
  if (!objs.is_array()) rd.fail("objects", "expected a list");
  std::set<int> ids;
  for (size_t i = 0; i < objs.size(); ++i) {
    const std::string w = "objects[" + std::to_string(i) + "]";
    const json& j = objs[i];
    TruthObject o;
    o.id = rd.integer(rd.field(j, w, "id"), w + ".id");
    if (o.id <= 0) rd.fail(w + ".id", "must be > 0 (label 0 is structure)");
    if (!ids.insert(o.id).second) rd.fail(w + ".id", "duplicate id " + std::to_string(o.id));
    o.class_name = rd.text(rd.field(j, w, "class"), w + ".class");
    const json& dyn = rd.field(j, w, "dynamic");
    if (!dyn.is_boolean()) rd.fail(w + ".dynamic", "expected true or false");
    o.dynamic = dyn.get<bool>();
    const json& poses = rd.field(j, w, "poses");
    if (!poses.is_object()) rd.fail(w + ".poses", "expected an object keyed by mission name");
    for (auto it = poses.begin(); it != poses.end(); ++it) {
      check_mission(rd, g.missions, it.key(), w + ".poses");
      if (it.value().is_null()) o.poses[it.key()] = std::nullopt;
      else o.poses[it.key()] = rd.rigid(it.value(), w + ".poses." + it.key());
    }
    for (const auto& m : g.missions)
      if (!o.poses.count(m)) o.poses[m] = std::nullopt;  // absent = not there
    g.objects.push_back(std::move(o));
  }
  return g;
}

}  // namespace lista::io
