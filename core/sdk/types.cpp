// Small methods of the SDK's data types.
#include <lista/data.hpp>

#include <cmath>
#include <set>
#include <string>

namespace lista {

size_t Mission::point_count() const {
  size_t n = 0;
  for (const auto& s : scans) n += s.points ? s.points->size() : 0;
  return n;
}

const Mission* MissionSet::find(const std::string& name) const {
  for (const auto& m : missions)
    if (m.name == name) return &m;
  return nullptr;
}

size_t MissionPoints::total() const {
  size_t n = 0;
  for (const auto& s : sets) n += s.size();
  return n;
}

void Object::update_geometry() {
  centroid = points.centroid();
  points.bounds(bbox_min, bbox_max);
}

const Object* ObjectSet::find(int id) const {
  for (const auto& o : objects)
    if (o.id == id) return &o;
  return nullptr;
}

void ObjectSet::renumber() {
  for (size_t i = 0; i < objects.size(); ++i) objects[i].id = static_cast<int>(i);
}

int DescriptorSet::row_of(int object_id) const {
  for (size_t i = 0; i < object_ids.size(); ++i)
    if (object_ids[i] == object_id) return static_cast<int>(i);
  return -1;
}

std::string contract_problem(const DescriptorSet& d) {
  const size_t rows = size_t(d.values.rows());
  if (rows != d.object_ids.size())
    return "descriptors have " + std::to_string(rows) + " rows but " + std::to_string(d.object_ids.size()) +
           " object ids (one row per object)";
  if (rows > 0 && d.values.cols() == 0)
    return "descriptors have no columns (0-d): every object needs at least one value";
  std::set<int> ids;
  for (int id : d.object_ids)
    if (!ids.insert(id).second) return "descriptors name object " + std::to_string(id) + " twice";
  for (size_t i = 0; i < rows; ++i) {
    const auto row = d.values.row(long(i));
    if (!row.allFinite())
      return "the descriptor of object " + std::to_string(d.object_ids[i]) + " holds a NaN or infinite value";
    if (d.normalized && std::abs(row.norm() - 1.0f) > 1e-3f)
      return "descriptors are marked normalized but the row of object " + std::to_string(d.object_ids[i]) +
             " has norm " + std::to_string(row.norm());
  }
  return {};
}

std::string contract_problem(const DescriptorSet& d, const ObjectSet& objects) {
  if (std::string why = contract_problem(d); !why.empty()) return why;
  std::set<int> wanted;
  for (const auto& o : objects.objects) wanted.insert(o.id);
  for (int id : d.object_ids)
    if (!wanted.count(id)) return "descriptors name object " + std::to_string(id) + ", which is not among the input objects";
  if (d.object_ids.size() != wanted.size())
    return "descriptors cover " + std::to_string(d.object_ids.size()) + " of " + std::to_string(wanted.size()) +
           " input objects (one row per object)";
  return {};
}

int Groups::group_of(int object_id) const {
  for (size_t i = 0; i < object_ids.size(); ++i)
    if (object_ids[i] == object_id) return group[i];
  return -1;
}

const char* to_string(ChangeStatus s) {
  switch (s) {
    case ChangeStatus::moved: return "moved";
    case ChangeStatus::removed: return "removed";
    case ChangeStatus::added: return "added";
  }
  return "?";
}

const ObjectChange* Matches::find(int object_id) const {
  for (const auto& o : objects)
    if (o.object_id == object_id) return &o;
  return nullptr;
}

ObjectChange* Matches::find(int object_id) {
  for (auto& o : objects)
    if (o.object_id == object_id) return &o;
  return nullptr;
}

const std::vector<std::string>& port_types() {
  static const std::vector<std::string> names{
      PortTraits<MissionSet>::name, PortTraits<MissionPoints>::name, PortTraits<ObjectSet>::name,
      PortTraits<DescriptorSet>::name, PortTraits<Groups>::name, PortTraits<Matches>::name};
  return names;
}

const Data& Inputs::at(const std::string& port) const {
  auto it = values_.find(port);
  if (it == values_.end()) throw Error("input port '" + port + "' is not connected");
  return it->second;
}

const Data& Outputs::at(const std::string& port) const {
  auto it = values_.find(port);
  if (it == values_.end()) throw Error("output port '" + port + "' was not produced");
  return it->second;
}

}  // namespace lista
