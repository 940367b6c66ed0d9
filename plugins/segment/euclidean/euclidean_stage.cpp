// segment.euclidean: PCL Euclidean cluster extraction per mission.
#include "euclidean_clustering.hpp"
#include <lista_segmentation/mission_objects.hpp>

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::segment {
namespace {

const ParamTable<EuclideanClusterConfig>& param_table() {
  using C = EuclideanClusterConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("tolerance", &C::tolerance, "joining distance").range(0.005, 5.0).unit("m");
    t.bind("min_points", &C::min_points, "smallest cluster kept").range(1, 2e9);
    t.bind("max_points", &C::max_points, "largest cluster kept").range(1, 2e9);
  });
}

class EuclideanSegmentStage : public Stage {
 public:
  explicit EuclideanSegmentStage(const Params& p) : config_(param_table().read(p)) {
    if (config_.max_points < config_.min_points) throw Error("max_points is below min_points");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.euclidean";
    i.version = "1.3.0";
    i.summary = "PCL Euclidean cluster extraction of the change points";
    i.doc =
        "PCL Euclidean cluster extraction of each mission's change points (points within tolerance share a "
        "cluster); clusters mostly seen free in their own mission are set apart as dynamics. "
        "Details: docs/segmentation.md, \"segment.euclidean\".";
    i.inputs = {{"changes", "points", "per-mission change points (common frame)"}};
    i.outputs = {{"objects", "objects", "one object per cluster per mission"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    ObjectSet objects = segmentation::objects_from_missions(
        in.get<MissionPoints>("changes"), context,
        [&](const PointSet& s, int) { return cluster_euclidean(s, config_); });
    context.record("objects", double(objects.objects.size()));
    return Outputs::of("objects", std::move(objects));
  }

 private:
  EuclideanClusterConfig config_;
};

}  // namespace
}  // namespace lista::segment

LISTA_STAGE_PLUGIN(lista::segment::EuclideanSegmentStage::info, lista::segment::EuclideanSegmentStage)
