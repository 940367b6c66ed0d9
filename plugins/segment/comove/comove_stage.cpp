// segment.comove: joins the pieces of one object that moved together
// (rule in comove_rule.hpp).
#include "comove_rule.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::segment {
namespace {

const ParamTable<ComoveConfig>& param_table() {
  using C = ComoveConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("slender_ratio", &C::slender_ratio, "a piece takes part when its height is at least this times its footprint's short side; 0 = every piece")
        .range(0, 100);
    t.bind("join_gap", &C::join_gap, "largest box-to-box gap between pieces of one object").range(0, 10).unit("m");
    t.bind("position_tolerance", &C::position_tolerance, "agreement of the seed pairs' centroid distances; a smaller move is none")
        .range(0.01, 2)
        .unit("m");
    t.bind("cover_radius", &C::cover_radius, "a moved point this near the other mission's pieces is covered")
        .range(0.01, 1)
        .unit("m");
    t.bind("cover_share", &C::cover_share, "share of a piece's points covered for it to join").range(0.01, 1);
    t.bind("max_extent", &C::max_extent, "longest footprint side of a joined object").range(0.1, 50).unit("m");
  });
}

class ComoveStage : public Stage {
 public:
  explicit ComoveStage(const Params& p) : c_(param_table().read(p)) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.comove";
    i.version = "1.0.0";
    i.summary = "Joins the pieces of one object that moved together (a table seen as its legs)";
    i.doc =
        "Joins the slender pieces that one rigid motion carries onto the other mission's pieces (a table a sparse "
        "scanner saw as its legs) into one object per mission. "
        "Details: docs/segmentation.md, \"segment.comove\".";
    i.inputs = {{"objects", "objects", "per-mission change clusters"}};
    i.outputs = {{"objects", "objects", "clusters, pieces that moved together joined"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    ComoveStats st;
    ObjectSet objects = join_comoving(in.get<ObjectSet>("objects"), c_, &st);
    for (uint32_t m : st.searches_cut)
      context.warn("segment.comove: the search between missions " + objects.missions[m] + " and " +
                   objects.missions[m + 1] +
                   " stopped at its budget (too many slender pieces in a regular layout); some pieces that moved "
                   "together may stay apart");
    context.record("joins", double(st.joins));
    context.record("joined_pieces", double(st.joined));
    context.record("objects", double(objects.objects.size()));
    return Outputs::of("objects", std::move(objects));
  }

 private:
  ComoveConfig c_;
};

}  // namespace
}  // namespace lista::segment

LISTA_STAGE_PLUGIN(lista::segment::ComoveStage::info, lista::segment::ComoveStage)
