// segment.overlap: merges and splits change clusters across consecutive
// missions by overlap ratio (rule in overlap_rule.hpp).
#include "overlap_rule.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::seg {
namespace {

const ParamTable<OverlapConfig>& param_table() {
  using C = OverlapConfig;
  static const ParamTable<C> table = [] {
    ParamTable<C> t;
    t.bind("margin", &C::margin, "bounding boxes grown by this").range(0, 2).unit("m");
    t.bind("merge_ratio", &C::merge_ratio, "share of a fragment inside the other mission's object").range(0.01, 1);
    t.bind("merge_gap", &C::merge_gap, "largest box-to-box gap between fragments").range(0, 5).unit("m");
    t.bind("split_ratio", &C::split_ratio, "share of each other-mission object inside the composite").range(0.01, 1);
    t.bind("min_points", &C::min_points, "smallest part of a split").range(1, 1e9);
    return t;
  }();
  return table;
}

class OverlapStage : public Stage {
 public:
  explicit OverlapStage(const Params& p) : c_(param_table().read(p)) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.overlap";
    i.version = "1.0.0";
    i.summary = "Merge/split of change clusters across consecutive missions by overlap ratio";
    i.doc =
        "inside(a, b) = share of a's points inside b's bounding box grown by `margin`. For each "
        "pair of consecutive missions: (1) merge - objects of one mission that each lie inside "
        "the same object of the other (inside >= merge_ratio) and are within merge_gap of each "
        "other become one (an object moved by less than its own size breaks into fragments, as "
        "only the non-overlapping parts of its two poses change); (2) split - an object that "
        "contains two or more objects of the other mission (inside >= split_ratio each) that stand "
        "more than merge_gap apart is cut, each point going to the nearest of them (objects touching in one mission, or "
        "one object replaced by several). The gap decides between the two readings: pieces within "
        "merge_gap are one object broken up, farther ones are separate objects. Merges run before splits; parts under min_points join "
        "the largest part. Ids are renumbered 0..n-1.";
    i.inputs = {{"objects", "objects", "per-mission change clusters"}};
    i.outputs = {{"objects", "objects", "clusters after merge and split"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    OverlapStats st;
    ObjectSet objects = merge_split_by_overlap(in.get<ObjectSet>("objects"), c_, &st);
    context.record("merged", double(st.merged));
    context.record("split", double(st.split));
    context.record("objects", double(objects.objects.size()));
    Outputs out;
    out.put("objects", std::move(objects));
    return out;
  }

 private:
  OverlapConfig c_;
};

void register_stages(Registrar& r) {
  r.add(OverlapStage::info(), [](const Params& p) { return std::make_unique<OverlapStage>(p); });
}

}  // namespace
}  // namespace lista::seg

LISTA_PLUGIN(lista::seg::register_stages)
