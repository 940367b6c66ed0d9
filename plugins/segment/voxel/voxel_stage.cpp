// segment.voxel: connected components over occupied voxels (union-find); the
// fast default segmenter.
#include <lista_segmentation/mission_objects.hpp>
#include <lista_segmentation/voxel_clustering.hpp>

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::segment {
namespace {

const ParamTable<segmentation::VoxelClusterConfig>& param_table() {
  using C = segmentation::VoxelClusterConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("tolerance", &C::tolerance, "voxel edge and joining distance").range(0.005, 5.0).unit("m");
    t.choice("connectivity", &C::exact, {{"voxel", false}, {"exact", true}},
             "join touching voxels, or points within tolerance");
    t.bind("min_points", &C::min_points, "smallest cluster kept").range(1, 1e9);
    t.bind("max_points", &C::max_points, "largest cluster kept").range(1, 1e12);
  });
}

class VoxelSegmentStage : public Stage {
 public:
  explicit VoxelSegmentStage(const Params& p) : config_(param_table().read(p)) {
    if (config_.max_points < config_.min_points)
      throw Error("max_points (" + std::to_string(config_.max_points) + ") is below min_points (" +
                  std::to_string(config_.min_points) + ")");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.voxel";
    i.version = "1.3.0";
    i.summary = "Connected components of the change over a voxel grid (union-find)";
    i.doc =
        "Connected components of each mission's change points over a voxel grid (union-find; connectivity exact "
        "gives PCL's Euclidean clusters); clusters mostly seen free in their own mission are set apart as dynamics. "
        "Details: docs/segmentation.md, \"segment.voxel\".";
    i.inputs = {{"changes", "points", "per-mission change points (common frame)"}};
    i.outputs = {{"objects", "objects", "one object per cluster per mission"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    const auto& changes = in.get<MissionPoints>("changes");
    ObjectSet objects = segmentation::objects_from_missions(
        changes, context, [&](const PointSet& s, int) { return segmentation::cluster_voxels(s.xyz, config_); });
    context.record("objects", double(objects.objects.size()));
    return Outputs::of("objects", std::move(objects));
  }

 private:
  segmentation::VoxelClusterConfig config_;
};

}  // namespace
}  // namespace lista::segment

LISTA_STAGE_PLUGIN(lista::segment::VoxelSegmentStage::info, lista::segment::VoxelSegmentStage)
