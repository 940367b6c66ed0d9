// filter.box: keeps the change points inside a region of interest.
#include <lista/data.hpp>
#include <lista/missions.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cmath>

namespace lista::filter {
namespace {

struct BoxConfig {
  std::vector<double> min = {-1e9, -1e9, -1e9};  // m
  std::vector<double> max = {1e9, 1e9, 1e9};     // m
  double max_height_above_floor = 0.0;           // m, 0 = off
  double floor_quantile = 0.01;
};

const ParamTable<BoxConfig>& param_table() {
  using C = BoxConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("min", &C::min, "lower corner [x, y, z]").unit("m");
    t.bind("max", &C::max, "upper corner [x, y, z]").unit("m");
    t.bind("max_height_above_floor", &C::max_height_above_floor, "drop points higher above the floor; 0 = off")
        .range(0.0, 1e4)
        .unit("m");
    t.bind("floor_quantile", &C::floor_quantile, "quantile of z taken as the floor height").range(0.0, 0.5);
  });
}

class BoxFilterStage : public Stage {
 public:
  explicit BoxFilterStage(const Params& p) {
    const BoxConfig c = param_table().read(p);
    if (c.min.size() != 3 || c.max.size() != 3) throw Error("min and max must have 3 values [x, y, z]");
    for (int a = 0; a < 3; ++a) {
      if (c.min[a] > c.max[a]) throw Error("min must not exceed max on every axis");
      min_[a] = float(c.min[a]), max_[a] = float(c.max[a]);
    }
    ceiling_ = c.max_height_above_floor;
    floor_quantile_ = c.floor_quantile;
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "filter.box";
    i.version = "1.0.0";
    i.summary = "Region of interest: keeps change points inside an axis-aligned box";
    i.doc =
        "Keeps the change points inside an axis-aligned box of the common frame; optionally also drops those more "
        "than max_height_above_floor above a robust floor level (cuts ceilings). "
        "Details: docs/segmentation.md, \"filter.box\".";
    i.inputs = {{"changes", "points", "per-mission change points"},
                {"missions", "missions", "the aligned missions; the floor is read from their points", true}};
    i.outputs = {{"changes", "points", "the points inside the region"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    const auto& changes = in.get<MissionPoints>("changes");
    std::vector<std::vector<uint32_t>> keep(changes.sets.size());
    for (size_t m = 0; m < changes.sets.size(); ++m) {
      const auto& s = changes.sets[m];
      for (uint32_t i = 0; i < s.size(); ++i)
        if (inside(s.xyz[i])) keep[m].push_back(i);
    }
    if (ceiling_ > 0) {
      std::vector<float> z = in.has("missions") ? heights(in.get<MissionSet>("missions"))
                                                 : heights(changes, keep);
      if (!z.empty()) {
        const float floor_z = geometry::kth_smallest(z, size_t(floor_quantile_ * double(z.size() - 1)));
        const float top = float(floor_z + ceiling_);
        context.record("floor_z", floor_z);
        for (size_t m = 0; m < keep.size(); ++m)
          keep[m].erase(std::remove_if(keep[m].begin(), keep[m].end(),
                                       [&](uint32_t i) { return changes.sets[m].xyz[i].z() > top; }),
                        keep[m].end());
      }
    }
    MissionPoints out;
    out.missions = changes.missions;
    size_t kept = 0;
    for (size_t m = 0; m < keep.size(); ++m) {
      out.sets.push_back(changes.sets[m].select(keep[m]));
      kept += keep[m].size();
    }
    context.record("kept_points", double(kept));
    context.record("removed_points", double(changes.total() - kept));
    return Outputs::of("changes", std::move(out));
  }

 private:
  bool inside(const Eigen::Vector3f& p) const { return (p.array() >= min_.array()).all() && (p.array() <= max_.array()).all(); }

  // Heights of the kept change points.
  static std::vector<float> heights(const MissionPoints& changes, const std::vector<std::vector<uint32_t>>& keep) {
    std::vector<float> z;
    for (size_t m = 0; m < keep.size(); ++m)
      for (auto i : keep[m]) z.push_back(changes.sets[m].xyz[i].z());
    return z;
  }

  // Heights of the missions' points inside the box, every k-th point of
  // every scan (about kSamples in all): the floor is the scene's, not the
  // lowest change's, so it holds when no change stands on the floor.
  std::vector<float> heights(const MissionSet& missions) const {
    constexpr size_t kSamples = 400000;
    size_t total = 0;
    for (const Mission& m : missions.missions)
      for (const Scan& s : m.scans) total += s.points ? s.points->size() : 0;
    const size_t step = std::max<size_t>(1, total / kSamples);
    std::vector<float> z;
    for (const Mission& m : missions.missions)
      for (size_t i = 0; i < m.scans.size(); ++i) {
        if (!m.scans[i].points) continue;
        const Eigen::Isometry3f to_common = m.sensor_to_common(i).cast<float>();
        const auto& xyz = m.scans[i].points->xyz;
        for (size_t j = 0; j < xyz.size(); j += step) {
          const Eigen::Vector3f p = to_common * xyz[j];
          if (inside(p)) z.push_back(p.z());
        }
      }
    return z;
  }

  Eigen::Vector3f min_, max_;
  double ceiling_ = 0, floor_quantile_ = 0.01;
};

}  // namespace
}  // namespace lista::filter

LISTA_STAGE_PLUGIN(lista::filter::BoxFilterStage::info, lista::filter::BoxFilterStage)
