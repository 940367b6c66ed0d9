// segment.voxel: connected components over occupied voxels (union-find); the
// fast default segmenter.
#include <lista_segmentation/mission_objects.hpp>
#include <lista_segmentation/voxel_clustering.hpp>

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::seg {
namespace {

// The clustering's settings; connectivity names its `exact` switch.
struct VoxelStageConfig : VoxelClusterConfig {
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
        "Cuts each mission's change points into objects. connectivity = \"voxel\": occupied voxels "
        "of edge `tolerance` are joined when they touch (26-neighbourhood); any two points closer "
        "than `tolerance` share a cluster and no join spans more than 2*sqrt(3)*tolerance. "
        "connectivity = \"exact\": points are joined when within `tolerance`, the same clusters "
        "as segment.euclidean at that tolerance; the grid only limits the neighbour search. "
        "Clusters outside [min_points, max_points] are dropped; clusters mostly seen free in their own "
        "mission are dynamics, not objects. Missions run in parallel. docs/segmentation.md.";
    i.inputs = {{"changes", "points", "per-mission change points (common frame)"}};
    i.outputs = {{"objects", "objects", "one object per cluster per mission"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    const auto& changes = in.get<MissionPoints>("changes");
    ObjectSet objects = objects_from_missions(
        changes, context, [&](const PointSet& s, int) { return cluster_voxels(s.xyz, config_); });
    context.record("objects", double(objects.objects.size()));
    Outputs out;
    out.put("objects", std::move(objects));
    return out;
  }

 private:
  VoxelClusterConfig config_;
};

void register_stages(Registrar& r) {
  r.add(VoxelSegmentStage::info(),
        [](const Params& p) { return std::make_unique<VoxelSegmentStage>(p); });
}

}  // namespace
}  // namespace lista::seg

LISTA_PLUGIN(lista::seg::register_stages)
