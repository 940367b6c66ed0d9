// segment.region-growing: PCL region growing with normals per mission.
#include <lista_segmentation/mission_objects.hpp>
#include "region_growing.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::segment {
namespace {

const ParamTable<RegionGrowingConfig>& param_table() {
  using C = RegionGrowingConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("normal_neighbours", &C::normal_neighbours, "k nearest points for each normal").range(3, 500);
    t.bind("neighbours", &C::neighbours, "k nearest points tested while growing").range(3, 500);
    t.bind("smoothness", &C::smoothness_deg, "largest normal angle between neighbours").range(0.1, 180).unit("deg");
    t.bind("curvature", &C::curvature, "growth continues only from points flatter than this (1 = any)").range(0, 1);
    t.bind("min_points", &C::min_points, "smallest region kept").range(1, 2e9);
    t.bind("max_points", &C::max_points, "largest region kept").range(1, 2e9);
  });
}

class RegionGrowingStage : public Stage {
 public:
  explicit RegionGrowingStage(const Params& p) : c_(param_table().read(p)) {
    if (c_.max_points < c_.min_points) throw Error("max_points is below min_points");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.region-growing";
    i.version = "1.3.0";
    i.summary = "PCL region growing with normals: splits clusters that touch";
    i.doc =
        "PCL region growing with normals: splits change clusters that touch along a crease, at the price of "
        "faceted objects falling into faces; clusters mostly seen free in their own mission are set apart as "
        "dynamics. "
        "Details: docs/segmentation.md, \"segment.region-growing\".";
    i.inputs = {{"changes", "points", "per-mission change points (common frame)"}};
    i.outputs = {{"objects", "objects", "one object per region per mission"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    ObjectSet objects = segmentation::objects_from_missions(
        in.get<MissionPoints>("changes"), context,
        [&](const PointSet& s, int threads) { return cluster_region_growing(s, c_, threads); });
    context.record("objects", double(objects.objects.size()));
    return Outputs::of("objects", std::move(objects));
  }

 private:
  RegionGrowingConfig c_;
};

}  // namespace
}  // namespace lista::segment

LISTA_STAGE_PLUGIN(lista::segment::RegionGrowingStage::info, lista::segment::RegionGrowingStage)
