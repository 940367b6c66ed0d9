// filter.morphology: removes noise and thin slivers from the change by a
// morphological opening on voxels; outputs the original points that survive.
#include "morphology.hpp"

#include <lista/data.hpp>
#include <lista/parallel.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::filter {
namespace {

const ParamTable<MorphologyConfig>& param_table() {
  using C = MorphologyConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("voxel", &C::voxel, "voxel edge").range(0.005, 5.0).unit("m");
    t.bind("min_neighbours", &C::min_neighbours, "occupied 26-neighbours a voxel needs to survive erosion")
        .range(0, 26);
    t.bind("dilate_steps", &C::dilate_steps, "dilations by the 3x3x3 cube after erosion (without reconstruct)")
        .range(0, 10);
    t.bind("reconstruct", &C::reconstruct, "dilate until stable: keep whole every component with a core");
  });
}

class MorphologyFilterStage : public Stage {
 public:
  explicit MorphologyFilterStage(const Params& p) : c_(param_table().read(p)) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "filter.morphology";
    i.version = "1.0.0";
    i.summary = "Erosion then dilation on the voxelised change (noise and sliver removal)";
    i.doc =
        "Morphological opening of the voxelised change: a rank-filter erosion drops isolated points and thin "
        "strips, and dilation (by default until stable: opening by reconstruction) restores what is connected to a "
        "surviving core. Outputs the original points. "
        "Details: docs/segmentation.md, \"filter.morphology\".";
    i.inputs = {{"changes", "points", "per-mission change points"}};
    i.outputs = {{"changes", "points", "the points whose voxel survives the opening"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    const auto& changes = in.get<MissionPoints>("changes");
    const size_t m = changes.sets.size();
    MissionPoints out;
    out.missions = changes.missions;
    out.sets.resize(m);
    parallel_for(m, context.threads(),
                 [&](size_t i) { out.sets[i] = changes.sets[i].select(morphology_keep(changes.sets[i], c_)); });
    context.record("removed_points", double(changes.total() - out.total()));
    return Outputs::of("changes", std::move(out));
  }

 private:
  MorphologyConfig c_;
};

}  // namespace
}  // namespace lista::filter

LISTA_STAGE_PLUGIN(lista::filter::MorphologyFilterStage::info, lista::filter::MorphologyFilterStage)
