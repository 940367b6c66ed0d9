// match.weighted: the paper's correspondence step (weighted physical +
// descriptor distance, optimal assignment per consecutive mission pair).
#include "weighted_matcher.hpp"

#include <lista/lista.hpp>

namespace lista::matching {

namespace {

class WeightedMatchStage : public Stage {
 public:
  explicit WeightedMatchStage(const Params& p) {
    cfg_.alpha = p.get<double>("alpha");
    cfg_.beta = p.get<double>("beta");
    cfg_.normalization = p.get<std::string>("normalization");
    cfg_.group_mode = p.get<std::string>("group_mode");
    cfg_.group_penalty = p.get<double>("group_penalty");
    cfg_.max_distance = p.get<double>("max_distance");
    cfg_.max_size_change = p.get<double>("max_size_change");
    cfg_.size_slack = p.get<double>("size_slack");
    cfg_.max_descriptor_distance = p.get<double>("max_descriptor_distance");
    cfg_.max_cost = p.get<double>("max_cost");
    if (cfg_.alpha + cfg_.beta <= 0.0) throw Error("alpha + beta must be > 0");
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& objects = in.get<ObjectSet>("objects");
    const auto& descriptors = in.get<DescriptorSet>("descriptors");
    const Groups* groups = in.has("groups") ? &in.get<Groups>("groups") : nullptr;
    std::string warning;
    Matches m = match_weighted(objects, descriptors, groups, cfg_, &warning);
    if (!warning.empty()) ctx.warn(warning);
    int moved = 0, removed = 0, added = 0;
    for (const auto& c : m.objects) {
      if (c.status == ChangeStatus::moved) ++moved;
      else if (c.status == ChangeStatus::removed) ++removed;
      else ++added;
    }
    ctx.info(std::to_string(moved) + " moved, " + std::to_string(removed) + " removed, " +
             std::to_string(added) + " added");
    ctx.record("moved", moved);
    ctx.record("removed", removed);
    ctx.record("added", added);
    Outputs out;
    out.put("matches", std::move(m));
    return out;
  }

 private:
  WeightedMatchConfig cfg_;
};

StageInfo info() {
  StageInfo s;
  s.name = "match.weighted";
  s.version = "1.0.0";
  s.summary = "Object correspondences by weighted physical + descriptor distance, optimal assignment";
  s.doc =
      "For each pair of consecutive missions, the cost of pairing object i (earlier) with j (later) is "
      "alpha * norm(centroid distance) + beta * norm(descriptor L2 distance) (+ group_penalty across groups "
      "when group_mode = soft). normalization = max divides the physical term by its largest candidate "
      "value and the descriptor term by the largest descriptor distance between any two objects; minmax is the paper's (x - min) / (max - min), which stretches descriptor noise between identical "
      "objects to the full range. Candidates must lie within max_distance metres, keep their size (height and principal horizontal extents within max(max_size_change x the larger, size_slack)), max_descriptor_distance "
      "(if > 0) and cost <= max_cost (< 0: alpha + beta). The Hungarian algorithm picks the cheapest set "
      "of pairs, each pair only if cheaper than leaving both unmatched. Matched objects are 'moved' (match "
      "= partner in the next mission, else the previous one); unmatched earlier objects 'removed', later "
      "ones 'added'. history chains matches across all missions. Confidence of a move = 0.5 * (1 - "
      "ambiguity) + 0.5 * group confidence, ambiguity = w / (cost of the best rival pair of either end); "
      "of an unmatched object = 0.5 * min(1, cheapest rejected candidate cost / max_cost; 1 if none) + "
      "0.5 * group confidence.";
  s.inputs = {{"objects", "objects", "changed objects of all missions"},
              {"descriptors", "descriptors", "one descriptor per object"},
              {"groups", "groups", "descriptor groups (soft or hard constraint)", true}};
  s.outputs = {{"matches", "matches", "status, partner, cost, confidence and history of every object"}};
  s.params = {
      ParamSpec::real("alpha", 0.5, "weight of the normalised physical distance").range(0.0, 100.0),
      ParamSpec::real("beta", 0.5, "weight of the normalised descriptor distance").range(0.0, 100.0),
      ParamSpec::text("normalization", "max", "how each distance is scaled to [0,1]").one_of({"max", "minmax"}),
      ParamSpec::text("group_mode", "soft", "how descriptor groups constrain pairs")
          .one_of({"soft", "hard", "ignore"}),
      ParamSpec::real("group_penalty", 0.5, "cost added to a cross-group pair (group_mode = soft)")
          .range(0.0, 100.0),
      ParamSpec::real("max_size_change", 0.3, "size gate: largest relative change of height or principal horizontal extents of a pair (a moved rigid object keeps its size); 0 = off")
          .range(0.0, 10.0),
      ParamSpec::real("size_slack", 0.15, "size change always allowed (partial views, noise)").range(0.0, 10.0).unit("m"),
      ParamSpec::real("max_distance", 30.0, "farthest centroid displacement accepted as a move (room or site scale: the size gate keeps unlike objects apart)")
          .range(0.0, 1e6).unit("m"),
      ParamSpec::real("max_descriptor_distance", 0.0, "largest descriptor distance of a pair; 0 = no gate")
          .at_least(0.0),
      ParamSpec::real("max_cost", -1.0, "largest weighted cost of a pair; < 0 = alpha + beta").range(-1.0, 1e6),
  };
  return s;
}

void register_stages(Registrar& r) {
  r.add(info(), [](const Params& p) { return std::make_unique<WeightedMatchStage>(p); });
}

}  // namespace

}  // namespace lista::matching

LISTA_PLUGIN(lista::matching::register_stages)
