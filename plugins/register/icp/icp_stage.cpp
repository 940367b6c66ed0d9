// register.icp: refines each moved object's transform with PCL (G)ICP from
// the SVD guess, its axis flips and yaw hypotheses; see lista_objreg/icp_refine.hpp.
#include <lista_objreg/register_objects.hpp>
#include <lista_objreg/icp_refine.hpp>
#include <lista_objreg/upright.hpp>

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <algorithm>
#include <mutex>
#include <numeric>
#include <vector>

namespace lista::registration {

namespace {

using namespace objreg;  // what common/objreg shares with match.weighted and segment.complete

// The registration's settings and the stage's own: the floor gate.
struct IcpStageConfig : IcpConfig {
  double max_lift = 0.15;  // m
  double max_tilt = 20.0;  // deg
};

const ParamTable<IcpStageConfig>& param_table();

class IcpStage : public Stage {
 public:
  explicit IcpStage(const Params& p) : IcpStage(param_table().read(p)) {}
  explicit IcpStage(const IcpStageConfig& c) : cfg_(c), max_lift_(c.max_lift), max_tilt_(c.max_tilt) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& objects = in.get<ObjectSet>("objects");
    const auto& matches = in.get<Matches>("matches");
    std::mutex mutex;
    std::vector<double> inlier_ratios;  // in the order the pairs finish
    int ambiguous = 0;
    Matches out = register_matches(objects, matches, [&](const Object& s, const Object& t) {
      IcpConfig cfg = cfg_;
      // Both standing on floors: moved on the floor, so upright poses only,
      // searched from base on base while the lift is gated (match.weighted's
      // floor gate judged the pair the same way).
      if (max_lift_ > 0.0 || max_tilt_ < 180.0) {
        cfg.admissible = [&](const Eigen::Isometry3d& pose) { return stays_on_floor(s, t, pose, max_lift_, max_tilt_); };
        if (max_lift_ > 0.0) cfg.floor_lift = floor_lift(s, t);
      }
      const IcpResult r = icp_refine(s.points.xyz, t.points.xyz, cfg);
      std::lock_guard<std::mutex> lock(mutex);
      inlier_ratios.push_back(r.inlier_ratio);
      if (!r.alternatives.empty()) ++ambiguous;
      return PairPose{r.transform, r.alternatives};
    }, ctx);
    out.method = matches.method + "+register.icp";
    // Summed in sorted order: the pairs finish in any order across threads,
    // and a float sum in that order differs in the last bit between runs.
    std::sort(inlier_ratios.begin(), inlier_ratios.end());
    const size_t pairs = inlier_ratios.size();
    if (pairs > 0)
      ctx.record("mean_inlier_ratio", std::accumulate(inlier_ratios.begin(), inlier_ratios.end(), 0.0) / double(pairs));
    ctx.record("pairs", double(pairs));
    ctx.record("ambiguous_pairs", ambiguous);
    return Outputs::of("matches", std::move(out));
  }

 private:
  IcpConfig cfg_;
  double max_lift_, max_tilt_;
};

StageInfo info() {
  StageInfo s;
  s.name = "register.icp";
  s.version = "1.6.1";
  s.summary = "6-DoF transform of each moved object by (G)ICP from SVD and yaw hypotheses";
  s.doc =
      "Refines each moved pair's 6-DoF transform by (G)ICP from several starts (SVD guess and flips, yaw turns, "
      "corner on corner), keeps the least turned of the poses that fit about as well and lists the others as "
      "alternative_transforms. "
      "Details: docs/matching.md, \"register.icp\".";
  s.inputs = {{"objects", "objects", "changed objects"}, {"matches", "matches", "statuses and partners"}};
  s.outputs = {{"matches", "matches", "the matches with a refined transform for every moved object"}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<IcpStageConfig>& param_table() {
  using C = IcpStageConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.choice("method", &C::method, {{"gicp", objreg::PairMethod::gicp}, {"icp", objreg::PairMethod::icp}},
             "registration algorithm");
    t.bind("voxel", &C::voxel, "voxel size for downsampling before ICP; 0 = none").range(0.0, 1.0).unit("m");
    t.bind("max_correspondence", &C::max_correspondence, "largest point pair distance ICP uses").range(0.001, 10.0).unit("m");
    t.bind("max_iterations", &C::max_iterations, "ICP iterations per hypothesis").range(1, 10000);
    t.bind("yaw_hypotheses", &C::yaw_hypotheses, "initial rotations about the vertical; 0 = none").range(0, 360);
    t.bind("svd_flips", &C::svd_flips, "also start from the four axis flips of the SVD guess");
    t.bind("corner_hypotheses", &C::corner_hypotheses,
           "views whose footprints differ in size, unexplained from the other starts, also start corner on corner (a partial view shares a corner with the whole, not its centre)");
    t.bind("inlier_distance", &C::inlier_distance, "score truncation distance").range(0.001, 10.0).unit("m");
    t.bind("symmetry_tolerance", &C::symmetry_tolerance, "relative score margin within which the smallest rotation wins")
        .range(0.0, 10.0);
    t.bind("distinct_degrees", &C::distinct_degrees,
           "a pose within symmetry_tolerance turned at least this far from the chosen one is reported "
           "as an alternative")
        .range(0.1, 180.0)
        .unit("deg");
    t.bind("distinct_metres", &C::distinct_metres,
           "a pose within symmetry_tolerance shifted at least this far (at the object's centroid) from the chosen one is reported as an alternative")
        .range(0.001, 100.0)
        .unit("m");
    t.bind("max_points", &C::max_points,
           "coarse pass: source points ICP iterates on from each hypothesis (evenly strided); 0 = all")
        .range(0, 100000000);
    t.bind("fine_max_points", &C::fine_max_points,
           "fine pass on the best few: source points ICP iterates on (evenly strided; at least max_points); 0 = all")
        .range(0, 100000000);
    t.bind("max_score_points", &C::max_score_points,
           "points each score queries each way (evenly strided; the searched cloud stays whole); 0 = all")
        .range(0, 100000000);
    t.bind("max_lift", &C::max_lift,
           "an object standing on floors in both missions (floor_z known) is registered upright: lifted by "
           "at most this relative to the floors (0 = no lift check)")
        .range(0.0, 10.0)
        .unit("m");
    t.bind("max_tilt", &C::max_tilt, "an object standing on floors in both missions is registered tilted by at most this (180 = any pose)").range(1.0, 180.0).unit("deg");
  });
}

}  // namespace

}  // namespace lista::registration

LISTA_STAGE_PLUGIN(lista::registration::info, lista::registration::IcpStage)
