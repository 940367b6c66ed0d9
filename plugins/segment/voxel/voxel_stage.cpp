// segment.voxel: connected components over occupied voxels (union-find); the
// fast default segmenter.
#include <lista_segmentation/mission_objects.hpp>
#include <lista_segmentation/voxel_clustering.hpp>

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::segment {
namespace {

// The clustering's settings; connectivity names its `exact` switch.
struct VoxelStageConfig : segmentation::VoxelClusterConfig {
  std::string connectivity = "voxel";
};

const ParamTable<VoxelStageConfig>& param_table() {
  using C = VoxelStageConfig;
  static const ParamTable<C> table = [] {
    ParamTable<C> t;
    t.bind("tolerance", &C::tolerance, "voxel edge and joining distance").range(0.005, 5.0).unit("m");
    t.bind("connectivity", &C::connectivity, "join touching voxels, or points within tolerance")
        .one_of({"voxel", "exact"});
    t.bind("min_points", &C::min_points, "smallest cluster kept").range(1, 1e9);
    t.bind("max_points", &C::max_points, "largest cluster kept").range(1, 1e12);
    return t;
  }();
  return table;
}

class VoxelSegmentStage : public Stage {
 public:
  explicit VoxelSegmentStage(const Params& p) {
    const VoxelStageConfig c = param_table().read(p);
    config_ = c;
    config_.exact = c.connectivity == "exact";
    if (config_.max_points < config_.min_points)
      throw Error("max_points (" + std::to_string(config_.max_points) + ") is below min_points (" +
                  std::to_string(config_.min_points) + ")");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.voxel";
    i.version = "1.1.0";
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
    Outputs out;
    out.put("objects", std::move(objects));
    return out;
  }

 private:
  segmentation::VoxelClusterConfig config_;
};

void register_stages(Registrar& r) {
  r.add(VoxelSegmentStage::info(),
        [](const Params& p) { return std::make_unique<VoxelSegmentStage>(p); });
}

}  // namespace
}  // namespace lista::segment

LISTA_PLUGIN(lista::segment::register_stages)
