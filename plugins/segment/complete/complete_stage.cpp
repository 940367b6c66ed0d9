// segment.complete: grows change clusters of objects moved by less than their
// own size into whole objects (rule in completion.hpp).
#include "completion.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::segment {
namespace {

const ParamTable<CompletionConfig>& param_table();

class CompleteStage : public Stage {
 public:
  explicit CompleteStage(const Params& p) : c_(param_table().read(p)) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.complete";
    i.version = "1.6.0";
    i.summary = "Grows partial change clusters of short moves into whole objects";
    i.doc =
        "Completes change clusters from each mission's full cloud: drops floor patches and unchanged thin "
        "surfaces, grows the slivers of short moves into whole objects, gives objects back their base, joins "
        "fragments, and measures the floor each object stands on. "
        "Details: docs/segmentation.md, \"segment.complete\".";
    i.inputs = {{"objects", "objects", "per-mission change clusters"},
                {"missions", "missions", "the aligned missions the clusters came from"}};
    i.outputs = {{"objects", "objects", "clusters, completed where a pair agreed"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    CompletionConfig c = c_;
    c.threads = context.threads();
    CompletionStats st;
    ObjectSet objects = complete_objects(in.get<ObjectSet>("objects"), in.get<MissionSet>("missions"), c, &st);
    for (const auto& note : st.pair_notes) context.debug(note);
    for (const auto& note : st.object_notes) context.debug(note);
    context.record("pairs", double(st.pairs));
    context.record("completed", double(st.completed));
    context.record("rejected", double(st.rejected));
    context.record("self_completed", double(st.self_completed));
    context.record("points_static", double(st.points_static));
    context.record("points_added", double(st.points_added));
    context.record("floors", double(st.floors));
    context.record("absorbed", double(st.absorbed));
    context.record("joined", double(st.joined));
    context.record("connected", double(st.connected));
    context.record("floor_only", double(st.floor_only));
    context.record("thin_static", double(st.thin_static));
    context.record("thin_surface", double(st.thin_surface));
    context.info("completed " + std::to_string(st.completed) + " of " + std::to_string(st.pairs) +
                 " pairs, " + std::to_string(st.points_added) + " points added" +
                 (st.floor_only ? ", " + std::to_string(st.floor_only) + " clusters of floor dropped" : "") +
                 (st.thin_static ? ", " + std::to_string(st.thin_static) + " unchanged thin surfaces dropped" : "") +
                 (st.thin_surface ? ", " + std::to_string(st.thin_surface) + " thin patches of a larger surface dropped" : "") +
                 (st.joined ? ", " + std::to_string(st.joined) + " fragments joined into completed pairs" : "") +
                 (st.connected ? ", " + std::to_string(st.connected) + " objects joined over changed points" : "") +
                 (st.absorbed ? ", " + std::to_string(st.absorbed) + " fragments joined to the object around them" : ""));
    return Outputs::of("objects", std::move(objects));
  }

 private:
  CompletionConfig c_;
};

const ParamTable<CompletionConfig>& param_table() {
  using C = CompletionConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("voxel", &C::voxel, "connectivity grid of the growth").range(0.01, 1).unit("m");
    t.bind("pair_gap", &C::pair_gap, "largest box-to-box gap of a pair").range(0, 10).unit("m");
    t.bind("box_margin", &C::box_margin, "growth region: union box of the pair grown by this").range(0, 2).unit("m");
    t.bind("floor_clearance", &C::floor_clearance, "least height above the local floor of an added point (4 sigma of the floor's noise if more)").range(0, 1).unit("m");
    t.bind("floor_percentile", &C::floor_percentile, "of the per-cell lowest points, the local floor").range(0, 1);
    t.bind("shape_tolerance", &C::shape_tolerance, "relative disagreement of the pair's extents allowed").range(0, 2);
    t.bind("shape_slack", &C::shape_slack, "absolute disagreement of the pair's extents allowed").range(0, 2).unit("m");
    t.choice("leak_growth", &C::leak_growth, {{"own_box", LeakGrowth::own_box}, {"base", LeakGrowth::base}},
             "what a growth leaking out of its region keeps: own_box = what it reaches inside the object's own box (a pair: the union of its two boxes); base = a self-completion its base only, a pair nothing");
    t.bind("self_complete", &C::self_complete, "also complete every object inside its own box grown by box_margin (its base, mostly)");
    t.bind("static_check", &C::static_check,
           "self-completion leaves out points every neighbouring mission also holds (see static_share)");
    // Shares of points: fractions in [0, 1].
    t.bind("static_share", &C::static_share,
           "share of a self-completion held unchanged by every neighbouring mission from which on those points are left out (also the thin-surface and join_connected share)")
        .range(0, 1);
    t.bind("nested_share", &C::nested_share,
           "share of an object's points inside the box of a larger object of its mission from which "
           "it joins that object (a fragment of it); 0 = never")
        .range(0, 1);
    t.bind("floor_share", &C::floor_share,
           "share of an object's points within the floor clearance from which it is the floor "
           "itself and dropped; 0 = never")
        .range(0, 1);
    t.bind("thin_height", &C::thin_height,
           "objects thinner than this whose voxels every neighbouring mission also holds (see "
           "static_share) are unchanged horizontal surfaces and dropped; 0 = never")
        .range(0, 1)
        .unit("m");
    t.bind("thin_surface_sides", &C::thin_surface_sides,
           "a thin object (thin_height) whose own mission continues its surface on at least this many "
           "of its four sides is a patch of an unchanged surface and dropped; 0 = never")
        .range(0, 4);
    t.bind("pair_retry", &C::pair_retry,
           "a pair whose growth is refused (leak or shapes) frees both objects for their next-nearest "
           "candidates; false = each object is offered its nearest candidate only");
    t.choice("pair_order", &C::pair_order, {{"centroid", PairOrder::centroid}, {"gap", PairOrder::gap}},
             "order of candidate pairs: by box gap in whole voxels, then by centroid distance (centroid) or object id (gap)");
    t.bind("join_fragments", &C::join_fragments,
           "join into a pair's object the other objects of its mission that its growth reaches, when the shapes then agree");
    t.bind("still_check", &C::still_check,
           "refuse a pair whose two grown objects, registered onto each other, fit best where they stand");
    t.bind("join_connected", &C::join_connected,
           "two objects of one mission that no completed pair holds are joined when a growth from one "
           "reaches the other over points mostly not held by the neighbouring missions (a table's "
           "legs without its top)");
    t.bind("max_leak", &C::max_leak, "occupied voxels found just outside the region, per voxel grown into, at most").range(0, 1);
  });
}

}  // namespace
}  // namespace lista::segment

LISTA_STAGE_PLUGIN(lista::segment::CompleteStage::info, lista::segment::CompleteStage)
