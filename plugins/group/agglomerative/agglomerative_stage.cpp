// group.agglomerative: hierarchical clustering of descriptors, the ablation
// alternative to group.kmeans. Same outputs and confidences (group_result.hpp).
#include "../kmeans/group_result.hpp"
#include "agglomerative.hpp"

#include <lista/lista.hpp>

namespace lista::grouping {

namespace {

class AgglomerativeStage : public Stage {
 public:
  explicit AgglomerativeStage(const Params& p)
      : linkage_(parse_linkage(p.get<std::string>("linkage"))),
        cut_(p.get<std::string>("cut")),
        k_(p.get<int>("k")),
        threshold_(p.get<double>("distance")),
        min_gap_(p.get<double>("min_gap")) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& d = in.get<DescriptorSet>("descriptors");
    check_descriptors(d);
    const Eigen::MatrixXd x = to_double(d);
    const int n = static_cast<int>(x.rows());
    const std::vector<Merge> merges = dendrogram(x, linkage_);
    int k = 0;
    if (cut_ == "k") k = std::min(k_, n);
    else if (cut_ == "distance") k = k_for_threshold(n, merges, threshold_);
    else k = k_at_largest_gap(n, merges, min_gap_);
    const std::vector<int> labels = cut_to_k(n, merges, k);
    ctx.info(std::to_string(n) + " objects in " + std::to_string(k) + " groups");
    ctx.record("k", k);
    Outputs out;
    out.put("groups", make_groups("group.agglomerative", d.object_ids, x, labels));
    return out;
  }

 private:
  Linkage linkage_;
  std::string cut_;
  int k_;
  double threshold_, min_gap_;
};

StageInfo info() {
  StageInfo s;
  s.name = "group.agglomerative";
  s.version = "1.0.0";
  s.summary = "Agglomerative (hierarchical) grouping of object descriptors";
  s.doc =
      "Bottom-up clustering of the descriptor rows (Euclidean) with single, average, complete or Ward "
      "linkage (Lance-Williams updates). The dendrogram is cut by `cut`: 'gap' (default) undoes the merges "
      "above the largest jump between successive merge heights (one group if no jump exceeds min_gap x "
      "the mean height, or fewer than 3 objects); 'distance' undoes merges above `distance`; 'k' keeps "
      "`k` groups. Confidences as group.kmeans: group = 1 - min-max normalised mean distance to the "
      "centroid, object = 1 - distance to its centroid / the largest such distance.";
  s.inputs = {{"descriptors", "descriptors", "one descriptor per object"}};
  s.outputs = {{"groups", "groups", "group per object with confidences"}};
  s.params = {
      ParamSpec::text("linkage", "average", "cluster distance").one_of({"single", "average", "complete", "ward"}),
      ParamSpec::text("cut", "gap", "how the dendrogram is cut").one_of({"gap", "distance", "k"}),
      ParamSpec::integer("k", 2, "groups kept with cut = 'k'").range(1, 100000),
      ParamSpec::real("distance", 1.0, "largest merge height kept with cut = 'distance' (descriptor units)")
          .at_least(0.0),
      ParamSpec::real("min_gap", 0.5, "cut = 'gap': smallest jump, as a multiple of the mean merge height, "
                                      "that splits the data")
          .at_least(0.0),
  };
  return s;
}

void register_stages(Registrar& r) {
  r.add(info(), [](const Params& p) { return std::make_unique<AgglomerativeStage>(p); });
}

}  // namespace

}  // namespace lista::grouping

LISTA_PLUGIN(lista::grouping::register_stages)
