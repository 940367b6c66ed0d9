// filter.box: keeps the change points inside a region of interest.
#include <lista/data.hpp>
#include <lista/plugin.hpp>

#include <algorithm>
#include <cmath>

namespace lista::filter {
namespace {

class BoxFilterStage : public Stage {
 public:
  explicit BoxFilterStage(const Params& p) {
    auto lo = p.get<std::vector<double>>("min"), hi = p.get<std::vector<double>>("max");
    if (lo.size() != 3 || hi.size() != 3) throw Error("min and max must have 3 values [x, y, z]");
    for (int a = 0; a < 3; ++a) {
      if (lo[a] > hi[a]) throw Error("min must not exceed max on every axis");
      min_[a] = float(lo[a]), max_[a] = float(hi[a]);
    }
    ceiling_ = p.get<double>("max_height_above_floor");
    floor_quantile_ = p.get<double>("floor_quantile");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "filter.box";
    i.version = "1.0.0";
    i.summary = "Region of interest: keeps change points inside an axis-aligned box";
    i.doc =
        "Keeps the points with min <= p <= max (common frame, every axis). Optionally also drops "
        "points more than `max_height_above_floor` above the floor, the floor being the "
        "`floor_quantile` quantile of z over the kept points of all missions (a robust lowest "
        "level, so a few points under the floor do not move it): the usual way to cut the "
        "ceiling without knowing the map's absolute heights. 0 disables it. Provenance is kept.";
    i.inputs = {{"changes", "points", "per-mission change points"}};
    i.outputs = {{"changes", "points", "the points inside the region"}};
    const double big = 1e9;
    i.params = {
        ParamSpec::real_list("min", {-big, -big, -big}, "lower corner [x, y, z]").unit("m"),
        ParamSpec::real_list("max", {big, big, big}, "upper corner [x, y, z]").unit("m"),
        ParamSpec::real("max_height_above_floor", 0.0, "drop points higher above the floor; 0 = off")
            .range(0.0, 1e4).unit("m"),
        ParamSpec::real("floor_quantile", 0.01, "quantile of z taken as the floor height").range(0.0, 0.5),
    };
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    const auto& changes = in.get<MissionPoints>("changes");
    std::vector<std::vector<uint32_t>> keep(changes.sets.size());
    for (size_t m = 0; m < changes.sets.size(); ++m) {
      const auto& s = changes.sets[m];
      for (uint32_t i = 0; i < s.size(); ++i)
        if ((s.xyz[i].array() >= min_.array()).all() && (s.xyz[i].array() <= max_.array()).all())
          keep[m].push_back(i);
    }
    if (ceiling_ > 0) {
      std::vector<float> z;
      for (size_t m = 0; m < keep.size(); ++m)
        for (auto i : keep[m]) z.push_back(changes.sets[m].xyz[i].z());
      if (!z.empty()) {
        auto nth = z.begin() + std::ptrdiff_t(floor_quantile_ * double(z.size() - 1));
        std::nth_element(z.begin(), nth, z.end());
        const float top = float(*nth + ceiling_);
        context.record("floor_z", *nth);
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
    Outputs o;
    o.put("changes", std::move(out));
    return o;
  }

 private:
  Eigen::Vector3f min_, max_;
  double ceiling_ = 0, floor_quantile_ = 0.01;
};

void register_stages(Registrar& r) {
  r.add(BoxFilterStage::info(), [](const Params& p) { return std::make_unique<BoxFilterStage>(p); });
}

}  // namespace
}  // namespace lista::filter

LISTA_PLUGIN(lista::filter::register_stages)
