// filter.mls: Moving Least Squares smoothing of the change points (PCL).
#include "mls_smoothing.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::filter {
namespace {

const ParamTable<MlsConfig>& param_table() {
  using C = MlsConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("radius", &C::radius, "neighbourhood radius of the fit").range(0.005, 5.0).unit("m");
    t.bind("polynomial_order", &C::polynomial_order, "order of the fitted surface").range(1, 3);
    t.bind("drop_unfitted", &C::drop_unfitted, "drop points with too few neighbours for a fit");
  });
}

class MlsFilterStage : public Stage {
 public:
  explicit MlsFilterStage(const Params& p) : c_(param_table().read(p)) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "filter.mls";
    i.version = "1.0.0";
    i.summary = "Moving Least Squares surface smoothing (PCL), one output per input point";
    i.doc =
        "Moving Least Squares smoothing (PCL): each change point is projected onto the surface fitted to its "
        "neighbours; positions change, provenance stays (output point k is input point k). "
        "Details: docs/segmentation.md, \"filter.mls\".";
    i.inputs = {{"changes", "points", "per-mission change points"}};
    i.outputs = {{"changes", "points", "the same points, smoothed positions"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    const auto& changes = in.get<MissionPoints>("changes");
    MissionPoints out;
    out.missions = changes.missions;
    size_t fitted_total = 0;
    for (const auto& s : changes.sets) {
      context.throw_if_cancelled();
      size_t fitted = 0;
      out.sets.push_back(mls_smooth(s, c_, context.threads(), &fitted));
      fitted_total += fitted;
    }
    context.record("fitted_points", double(fitted_total));
    return Outputs::of("changes", std::move(out));
  }

 private:
  MlsConfig c_;
};

}  // namespace
}  // namespace lista::filter

LISTA_STAGE_PLUGIN(lista::filter::MlsFilterStage::info, lista::filter::MlsFilterStage)
