// group.kmeans: the paper's grouping. Descriptors are clustered with K-means
// for K = 1..k_max and K is taken at the elbow of the WCSS curve (see
// kmeans.hpp for the exact rule), unless `k` fixes it.
#include <lista_grouping/group_result.hpp>
#include "kmeans.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <algorithm>

namespace lista::group {

namespace {

// K-means' settings and the stage's own: how K is chosen.
struct KMeansStageConfig : KMeansConfig {
  int k = 0;  // 0 = the elbow rule
  int k_max = 10;
};

const ParamTable<KMeansStageConfig>& param_table();

class KMeansStage : public Stage {
 public:
  explicit KMeansStage(const Params& p) : c_(param_table().read(p)) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& d = in.get<DescriptorSet>("descriptors");
    grouping::check_descriptors(d);
    const Eigen::MatrixXd x = grouping::to_double(d);
    const int n = static_cast<int>(x.rows());
    c_.seed = ctx.seed();
    Outputs out;
    if (n == 0) {
      Groups g;
      g.method = "group.kmeans";
      out.put("groups", std::move(g));
      return out;
    }

    KMeansResult chosen;
    int k = 0;
    if (c_.k > 0) {
      k = std::min(c_.k, n);
      chosen = kmeans(x, k, c_);
    } else {
      const int kmax = std::min(c_.k_max, n);
      std::vector<KMeansResult> runs(kmax);
      std::vector<double> wcss(kmax);
      for (int kk = 1; kk <= kmax; ++kk) {
        ctx.throw_if_cancelled();
        runs[kk - 1] = kmeans(x, kk, c_);
        wcss[kk - 1] = runs[kk - 1].wcss;
      }
      k = elbow_k(wcss);
      chosen = std::move(runs[k - 1]);
      std::string curve;
      for (double w : wcss) curve += (curve.empty() ? "" : " ") + std::to_string(w);
      ctx.debug("WCSS for K=1.." + std::to_string(kmax) + ": " + curve);
    }
    ctx.info(std::to_string(n) + " objects in " + std::to_string(k) + " groups");
    ctx.record("k", k);
    ctx.record("wcss", chosen.wcss);
    out.put("groups", grouping::make_groups("group.kmeans", d.object_ids, x, chosen.labels));
    return out;
  }

 private:
  KMeansStageConfig c_;
};

StageInfo info() {
  StageInfo s;
  s.name = "group.kmeans";
  s.version = "1.0.0";
  s.summary = "K-means grouping of object descriptors, K by the WCSS elbow";
  s.doc =
      "K-means grouping of the descriptor rows, K fixed or by the elbow of the within-cluster sum of squares; "
      "group confidence from compactness, object confidence from the distance to its centroid. "
      "Details: docs/descriptors.md, \"group.kmeans\".";
  s.inputs = {{"descriptors", "descriptors", "one descriptor per object"}};
  s.outputs = {{"groups", "groups", "group per object with confidences"}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<KMeansStageConfig>& param_table() {
  using C = KMeansStageConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("k", &C::k, "fixed number of groups; 0 = choose by the elbow rule").range(0, 1000);
    t.bind("k_max", &C::k_max, "largest K tried by the elbow rule").range(1, 1000);
    t.bind("restarts", &C::restarts, "k-means++ seedings per K; the lowest WCSS wins").range(1, 1000);
    t.bind("max_iterations", &C::max_iterations, "Lloyd iterations per seeding").range(1, 100000);
  });
}

}  // namespace

}  // namespace lista::group

LISTA_STAGE_PLUGIN(lista::group::info, lista::group::KMeansStage)
