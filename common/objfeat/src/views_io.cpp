#include <lista_objfeat/views.hpp>

#include <lista/error.hpp>
#include <lista_io/pcd.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <vector>

namespace lista::objfeat {

namespace {

// Appends one folder's views; `labels` numbers shapes across folders, so one
// shape id is one label in every folder (ids name the geometry); `variants`
// numbers the generator's own ids the same way.
void append_views(const std::string& folder, ViewChannels channels, std::map<std::string, int>& labels,
                  std::map<std::string, int>& variants, ViewSet& out) {
  auto source_index = [&out](const std::string& name) {
    auto it = std::find(out.sources.begin(), out.sources.end(), name);
    if (it != out.sources.end()) return int(it - out.sources.begin());
    out.sources.push_back(name);
    return int(out.sources.size()) - 1;
  };
  namespace fs = std::filesystem;
  const fs::path index_path = fs::path(folder) / "index.json";
  std::ifstream in(index_path);
  if (!in) throw Error(index_path.string() + ": not found (create it with `lista-sim views --out " + folder + "`)");
  nlohmann::json index;
  try {
    in >> index;
  } catch (const std::exception& e) {
    throw Error(index_path.string() + ": not valid JSON: " + e.what());
  }
  const std::string where = index_path.string();
  if (!index.is_object())
    throw Error(where + ": must be a JSON object with \"format\": \"lista-views/1\" and a \"views\" list");
  if (index.value("format", "") != "lista-views/1") throw Error(where + ": format is not 'lista-views/1'");
  if (!index.contains("views") || !index.at("views").is_array()) throw Error(where + ": \"views\" must be a list of views");
  if (index.contains("shapes") && !index.at("shapes").is_array()) throw Error(where + ": \"shapes\" must be a list");
  // A view's or shape's field, of the kind it must be, or an error naming it.
  auto text = [&](const nlohmann::json& j, const char* what, size_t k, const char* key) {
    if (!j.is_object() || !j.contains(key) || !j.at(key).is_string())
      throw Error(where + ": " + what + " " + std::to_string(k) + " needs \"" + key + "\" as text");
    return j.at(key).get<std::string>();
  };
  const size_t before = out.views.size();
  try {
    std::map<std::string, int> source_of;  // shape id -> source index
    std::map<std::string, std::array<float, 3>> extent_of;
    if (index.contains("shapes"))
      for (size_t k = 0; k < index.at("shapes").size(); ++k) {
        const auto& s = index.at("shapes")[k];
        const std::string id = text(s, "shape", k, "id");
        source_of[id] = source_index(s.value("source", "unknown"));
        if (s.contains("extent")) {
          const auto& j = s.at("extent");
          const bool numbers = j.is_array() && std::all_of(j.begin(), j.end(), [](const auto& x) { return x.is_number(); });
          const auto e = numbers ? j.get<std::vector<float>>() : std::vector<float>{};
          if (e.size() != 3 || !(e[0] > 0.f && e[1] > 0.f && e[2] > 0.f))
            throw Error(index_path.string() + ": shape '" + id + "' extent must be three positive sizes");
          extent_of[id] = {e[0], e[1], e[2]};
        }
      }
    for (size_t k = 0; k < index.at("views").size(); ++k) {
      const auto& v = index.at("views")[k];
      View view;
      const std::string shape = text(v, "view", k, "shape"), file = text(v, "view", k, "file");
      if (!v.contains("instance") || !v.at("instance").is_number_integer())
        throw Error(where + ": view " + std::to_string(k) + " needs \"instance\" as a whole number");
      view.label = labels.emplace(shape, int(labels.size())).first->second;
      view.variant = variants.emplace(v.value("variant", shape), int(variants.size())).first->second;
      view.instance = v.at("instance").get<int>();
      view.split = v.value("split", "train") == "train" ? 0 : 1;
      auto src = source_of.find(shape);
      view.source = src != source_of.end() ? src->second : source_index("unknown");
      if (auto e = extent_of.find(shape); e != extent_of.end()) view.extent = e->second;
      view.sensor = v.value("sensor", "");
      if (v.contains("distance")) {
        if (!v.at("distance").is_number())
          throw Error(index_path.string() + ": view '" + file + "' distance must be a number (metres)");
        view.distance = v.at("distance").get<float>();
      }
      view.points = io::read_scan((fs::path(folder) / file).string()).points;
      if (view.points.empty()) continue;
      // Ground truth must not reach a descriptor; swapping frees the memory
      // (clear() would keep it).
      std::vector<uint32_t>().swap(view.points.label);
      if (channels == ViewChannels::xyz_only) {
        std::vector<float>().swap(view.points.intensity);
        std::vector<uint32_t>().swap(view.points.scan);
        std::vector<uint32_t>().swap(view.points.index);
        view.points.xyz.shrink_to_fit();
      }
      out.views.push_back(std::move(view));
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(index_path.string() + ": " + e.what());
  }
  if (out.views.size() == before) throw Error(index_path.string() + ": no views");
}

}  // namespace

ViewSet read_views(const std::string& folder, ViewChannels channels) {
  return read_views(std::vector<std::string>{folder}, channels);
}

ViewSet read_views(const std::vector<std::string>& folders, ViewChannels channels) {
  if (folders.empty()) throw Error("no views folder given");
  ViewSet out;
  std::map<std::string, int> labels, variants;
  std::set<std::string> seen;
  for (const auto& f : folders) {
    // The same views twice would be each other's nearest neighbours.
    std::error_code ec;
    const std::string key = std::filesystem::weakly_canonical(f, ec).string();
    if (!seen.insert(ec ? f : key).second) throw Error(f + ": views folder given twice");
    append_views(f, channels, labels, variants, out);
  }
  return out;
}

}  // namespace lista::objfeat
