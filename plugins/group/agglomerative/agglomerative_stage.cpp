// group.agglomerative: hierarchical clustering of descriptors, the ablation
// alternative to group.kmeans. Same outputs and confidences (lista_grouping/group_result.hpp).
#include <lista_grouping/group_result.hpp>
#include "agglomerative.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <cstdio>

namespace lista::group {

namespace {

enum class Cut { gap, distance, k };

struct AgglomerativeConfig {
  Linkage linkage = Linkage::average;
  Cut cut = Cut::gap;
  int k = 2;
  double distance = 1.0;  // descriptor units
  double min_gap = 0.5;
  int k_max = 10;
};

const ParamTable<AgglomerativeConfig>& param_table();

class AgglomerativeStage : public Stage {
 public:
  explicit AgglomerativeStage(const Params& p) : c_(param_table().read(p)) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& d = in.get<DescriptorSet>("descriptors");
    grouping::check_descriptors(d);
    const Eigen::MatrixXd x = grouping::to_double(d);
    const int n = static_cast<int>(x.rows());
    const std::vector<Merge> merges = dendrogram(x, c_.linkage);
    int k = 0;
    if (c_.cut == Cut::k) k = std::min(c_.k, n);
    else if (c_.cut == Cut::distance) k = k_for_threshold(n, merges, c_.distance);
    else k = gap_cut(n, merges, ctx);
    const std::vector<int> labels = cut_to_k(n, merges, k);
    ctx.info(std::to_string(n) + " objects in " + std::to_string(k) + " groups");
    ctx.record("k", k);
    return Outputs::of("groups", grouping::make_groups("group.agglomerative", d.object_ids, x, labels));
  }

 private:
  // One group is a finding (descriptors without classes), but it also makes
  // the grouping a no-op for matching: say so, with the jump that fell short.
  int gap_cut(int n, const std::vector<Merge>& merges, Context& ctx) const {
    const GapCut cut = cut_at_largest_gap(n, merges, c_.min_gap, c_.k_max);
    if (cut.best_k > 0) ctx.record("gap_jump", cut.jump);
    if (cut.k == 1 && cut.best_k > 0) {
      char line[256];
      std::snprintf(line, sizeof line,
                    "no jump between merge heights reaches min_gap %.2f (largest %.2f, at %d groups): one group for "
                    "%d objects; cut = 'k' fixes the number",
                    c_.min_gap, cut.jump, cut.best_k, n);
      ctx.warn(line);
    }
    return cut.k;
  }

  AgglomerativeConfig c_;
};

StageInfo info() {
  StageInfo s;
  s.name = "group.agglomerative";
  s.version = "1.0.0";
  s.summary = "Agglomerative (hierarchical) grouping of object descriptors";
  s.doc =
      "Hierarchical grouping of the descriptor rows (single, average, complete or Ward linkage), the dendrogram "
      "cut at its largest relative gap, at a distance or at k groups; confidences as group.kmeans. "
      "Details: docs/descriptors.md, \"group.agglomerative\".";
  s.inputs = {{"descriptors", "descriptors", "one descriptor per object"}};
  s.outputs = {{"groups", "groups", "group per object with confidences"}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<AgglomerativeConfig>& param_table() {
  using C = AgglomerativeConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.choice("linkage", &C::linkage,
             {{"single", Linkage::single}, {"average", Linkage::average}, {"complete", Linkage::complete},
              {"ward", Linkage::ward}},
             "cluster distance");
    t.choice("cut", &C::cut, {{"gap", Cut::gap}, {"distance", Cut::distance}, {"k", Cut::k}},
             "how the dendrogram is cut");
    t.bind("k", &C::k, "groups kept with cut = 'k'").range(1, 100000);
    t.bind("distance", &C::distance, "largest merge height kept with cut = 'distance' (descriptor units)")
        .at_least(0.0);
    t.bind("min_gap", &C::min_gap, "cut = 'gap': smallest relative jump between successive merge heights "
                                   "(h_above / h_below - 1) that splits the data")
        .at_least(0.0);
    t.bind("k_max", &C::k_max, "cut = 'gap': most groups considered (and at most half the objects)")
        .range(2, 100000);
  });
}

}  // namespace

}  // namespace lista::group

LISTA_STAGE_PLUGIN(lista::group::info, lista::group::AgglomerativeStage)
