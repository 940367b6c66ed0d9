// register.svd: the paper's registration of moved objects (shared centroid,
// orientation from the SVD of the covariance); see lista_objreg/svd_registration.hpp.
#include <lista_objreg/register_objects.hpp>
#include <lista_objreg/svd_registration.hpp>

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <atomic>

namespace lista::registration {

namespace {

using namespace objreg;  // what common/objreg shares with match.weighted and segment.complete

struct SvdConfig {
  double ambiguity_tolerance = 0.05;
};

const ParamTable<SvdConfig>& param_table() {
  using C = SvdConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("ambiguity_tolerance", &C::ambiguity_tolerance,
           "relative skew / variance gap below which a frame is reported ambiguous")
        .range(0.0, 1.0);
  });
}

class SvdStage : public Stage {
 public:
  explicit SvdStage(const Params& p) : tolerance_(param_table().read(p).ambiguity_tolerance) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& objects = in.get<ObjectSet>("objects");
    const auto& matches = in.get<Matches>("matches");
    std::atomic<int> ambiguous{0};
    Matches out = register_matches(objects, matches, [&](const Object& s, const Object& t) {
      const PrincipalFrame fs = principal_frame(s.points.xyz, tolerance_);
      const PrincipalFrame ft = principal_frame(t.points.xyz, tolerance_);
      if (fs.ambiguous_sign || fs.ambiguous_axes || ft.ambiguous_sign || ft.ambiguous_axes) ++ambiguous;
      return PairPose{svd_transform(fs, ft), {}};  // ambiguity is counted, not scored: no alternatives
    }, ctx);
    out.method = matches.method + "+register.svd";
    // Information, not a warning: pipelines/lista.toml refines these with
    // register.icp, which tries every flip; alone, the count is in the metrics.
    if (ambiguous > 0)
      ctx.info(std::to_string(ambiguous.load()) +
               " moved pairs have near-symmetric shapes; their SVD orientation may be off by a flip, which a "
               "register.icp stage after this one resolves");
    ctx.record("ambiguous_pairs", ambiguous.load());
    return Outputs::of("matches", std::move(out));
  }

 private:
  double tolerance_;
};

StageInfo info() {
  StageInfo s;
  s.name = "register.svd";
  s.version = "1.0.0";
  s.summary = "6-DoF transform of each moved object: shared centroid, orientation from covariance SVD";
  s.doc =
      "6-DoF transform of each moved pair from the two objects' principal frames (centroid and covariance SVD, "
      "axes signed by skew): a fast first guess; ambiguous frames are counted. "
      "Details: docs/matching.md, \"register.svd\".";
  s.inputs = {{"objects", "objects", "changed objects"}, {"matches", "matches", "statuses and partners"}};
  s.outputs = {{"matches", "matches", "the matches with a transform for every moved object"}};
  s.params = param_table().specs();
  return s;
}

}  // namespace

}  // namespace lista::registration

LISTA_STAGE_PLUGIN(lista::registration::info, lista::registration::SvdStage)
