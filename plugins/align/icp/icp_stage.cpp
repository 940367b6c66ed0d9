// align.icp: the naive baseline the paper argues against. Each mission's whole
// map (all scans in its map frame, voxel-downsampled) is registered onto the
// first mission's map with one rigid ICP/GICP. Poses are left as they are, so
// drift that bends one map against the other stays ("double walls").

#include <lista/lista.hpp>
#include <lista/param_table.hpp>
#include <lista_alignkit/cloud_ops.hpp>
#include <lista/parallel.hpp>
#include <lista_alignkit/level.hpp>
#include <lista_alignkit/registration.hpp>
#include <lista_alignkit/trajectory_error.hpp>

namespace lista::align {

using namespace alignkit;  // common/alignkit: clouds, registration, levelling

namespace {

Cloud mission_map(const Mission& m, double voxel, double max_range) {
  Cloud all;
  for (const auto& s : m.scans) {
    if (!s.points) continue;
    const Eigen::Isometry3f t = s.pose.cast<float>();
    for (const auto& p : s.points->xyz)
      if (p.squaredNorm() <= max_range * max_range) all.push_back(t * p);
    // Downsample as we go so that memory stays bounded by the map, not the scans.
    if (all.size() > 4000000) all = voxel_downsample(all, voxel);
  }
  return voxel_downsample(all, voxel);
}

Eigen::Vector3d centroid(const Cloud& c) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : c) sum += p.cast<double>();
  return c.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(c.size()));
}

// The stage's settings, flat: RegistrationOptions' defaults are
// align.posegraph's, and the map voxel is the registration's too.
enum class InitialGuess { identity, centroid, input };

struct IcpAlignConfig {
  double voxel = 0.25;      // m
  double max_range = 40.0;  // m
  RegistrationMethod registration = RegistrationMethod::gicp;
  InitialGuess initial = InitialGuess::centroid;
  double coarse_distance = 3.0;  // m
  double fine_distance = 0.5;    // m
  int iterations = 60;
  double min_overlap = 0.3;
  LevelConfig level;
};

const ParamTable<IcpAlignConfig>& param_table();

class IcpStage : public Stage {
 public:
  explicit IcpStage(const Params& p) : c_(param_table().read(p)) {
    reg_.method = c_.registration;
    reg_.voxel = c_.voxel;
    reg_.coarse_distance = c_.coarse_distance;
    reg_.fine_distance = c_.fine_distance;
    reg_.max_iterations = c_.iterations;
    reg_.inlier_distance = 2.0 * c_.voxel;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& set = in.get<MissionSet>("missions");
    if (set.missions.empty()) throw Error("no missions to align");
    if (const auto before = trajectory_error(set)) ctx.record("ate_before_m", before->rmse);
    MissionSet out = set;  // point data shared
    std::vector<Cloud> maps(set.missions.size());
    parallel_for(maps.size(), ctx.threads(), [&](size_t i) {
      maps[i] = mission_map(set.missions[i], c_.voxel, c_.max_range);
      if (maps[i].size() < 20) throw Error("mission '" + set.missions[i].name + "' has too few points to register");
    });
    // The first mission's frame is the common frame; with initial = "input"
    // it keeps the to_common it came with and the others start from theirs.
    const Eigen::Isometry3d reference = c_.initial == InitialGuess::input ? set.missions[0].to_common : Eigen::Isometry3d::Identity();
    out.missions[0].to_common = reference;
    for (size_t m = 1; m < maps.size(); ++m) {
      ctx.throw_if_cancelled();
      Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();  // mission m's map -> mission 0's map
      if (c_.initial == InitialGuess::centroid) guess.translation() = centroid(maps[0]) - centroid(maps[m]);
      if (c_.initial == InitialGuess::input) guess = reference.inverse() * set.missions[m].to_common;
      const RegistrationResult r = register_clouds(maps[m], maps[0], guess, reg_);
      const std::string& name = set.missions[m].name;
      ctx.record("overlap_" + name, r.overlap);
      ctx.record("rmse_" + name, r.inlier_rmse);
      if (!r.converged || r.overlap < c_.min_overlap)
        throw Error("mission '" + name + "' does not register onto '" + set.missions[0].name + "' (overlap " +
                    std::to_string(r.overlap) + " < min_overlap " + std::to_string(c_.min_overlap) +
                    "); the maps must overlap and start roughly aligned");
      out.missions[m].to_common = reference * r.transform;
    }
    level_common_frame(out, c_.level, ctx);
    if (const auto after = trajectory_error(out)) {
      ctx.record("ate_after_m", after->rmse);
      // One ICP per mission finds the nearest fit: maps that start turned
      // (another SLAM run's frame) or in a symmetric room can lock wrong.
      if (const std::string w = failed_alignment_warning(*after); !w.empty())
        ctx.warn(w + " (align.icp needs the missions' map frames roughly aligned; align.posegraph does not)");
    }
    return Outputs::of("missions", std::move(out));
  }

 private:
  IcpAlignConfig c_;
  RegistrationOptions reg_;
};

StageInfo icp_stage_info() {
  StageInfo s;
  s.name = "align.icp";
  s.version = "1.2.0";
  s.summary = "Baseline: one ICP/GICP per mission between whole mission maps";
  s.doc =
      "Registers each mission's whole map onto the first mission's with coarse-to-fine GICP (or ICP) and sets "
      "to_common; scan poses stay, so drift within a mission remains (the paper's baseline). The common frame "
      "is then levelled. "
      "Details: docs/alignment.md, \"align.icp\".";
  s.inputs = {{"missions", "missions", "missions, each in its own map frame"}};
  s.outputs = {{"missions", "missions", "missions with to_common set"}};
  s.params = param_table().specs();
  s.renamed = param_table().renames();
  return s;
}

const ParamTable<IcpAlignConfig>& param_table() {
  using C = IcpAlignConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("voxel", &C::voxel, "map downsampling").range(0.01, 10).unit("m");
    t.bind("max_range", &C::max_range, "points farther from their sensor are left out").range(0.5, 1000).unit("m");
    t.choice("registration", &C::registration, registration_method_names(),
             "gicp (PCL's Generalized ICP), gicp_gn (ours: GICP by Gauss-Newton) or icp (point to point)");
    t.choice("initial", &C::initial,
             {{"identity", InitialGuess::identity}, {"centroid", InitialGuess::centroid}, {"input", InitialGuess::input}},
             "starting guess: identity, centroid offset, or the input to_common");
    t.bind("coarse_distance", &C::coarse_distance, "max correspondence distance, coarse stage").range(0.05, 100).unit("m");
    t.bind("fine_distance", &C::fine_distance, "max correspondence distance, fine stage").range(0.01, 10).unit("m");
    t.bind("iterations", &C::iterations, "iterations per stage").range(1, 10000);
    t.bind("min_overlap", &C::min_overlap, "share of a map's points with a partner after registration").range(0, 1);
    // Declared once for every align.* stage that levels (lista_alignkit/level.hpp).
    bind_level(t, &C::level);
  });
}

}  // namespace

}  // namespace lista::align

LISTA_STAGE_PLUGIN(lista::align::icp_stage_info, lista::align::IcpStage)
