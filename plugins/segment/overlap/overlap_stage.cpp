// segment.overlap: merges and splits change clusters across consecutive
// missions by overlap ratio (rule in overlap_rule.hpp).
#include "overlap_rule.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::segment {
namespace {

const ParamTable<OverlapConfig>& param_table() {
  using C = OverlapConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("margin", &C::margin, "bounding boxes grown by this").range(0, 2).unit("m");
    t.bind("merge_ratio", &C::merge_ratio, "share of a fragment inside the other mission's object").range(0.01, 1);
    t.bind("merge_gap", &C::merge_gap, "largest box-to-box gap between fragments").range(0, 5).unit("m");
    t.bind("split_ratio", &C::split_ratio, "share of each other-mission object inside the composite").range(0.01, 1);
    t.bind("min_points", &C::min_points, "smallest part of a split").range(1, 1e9);
  });
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
        "Merges the fragments of one object and splits clusters that hold several objects, by how the clusters "
        "of consecutive missions lie inside each other. "
        "Details: docs/segmentation.md, \"segment.overlap\".";
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
    return Outputs::of("objects", std::move(objects));
  }

 private:
  OverlapConfig c_;
};

}  // namespace
}  // namespace lista::segment

LISTA_STAGE_PLUGIN(lista::segment::OverlapStage::info, lista::segment::OverlapStage)
