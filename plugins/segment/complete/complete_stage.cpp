// segment.complete: grows change clusters of objects moved by less than their
// own size into whole objects (rule in completion.hpp).
#include "completion.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

namespace lista::seg {
namespace {

// The completion's settings; leak_growth and pair_order name its switches.
struct CompleteStageConfig : CompletionConfig {
  std::string leak_growth = "own_box";
  std::string pair_order = "centroid";
};

const ParamTable<CompleteStageConfig>& param_table();

class CompleteStage : public Stage {
 public:
  explicit CompleteStage(const Params& p) {
    const CompleteStageConfig c = param_table().read(p);
    c_ = c;
    c_.centroid_order = c.pair_order == "centroid";
    c_.leak_own_box = c.leak_growth == "own_box";
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.complete";
    i.version = "1.6.0";
    i.summary = "Grows partial change clusters of short moves into whole objects";
    i.doc =
        "First, an object with at least floor_share of its points within the floor clearance of its local floor "
        "(below) is the floor itself, which the difference flags where beams graze uneven ground: it is dropped "
        "before anything pairs with it; so is an object thinner than thin_height whose voxels every neighbouring "
        "mission also holds (static_share of its points): an unchanged horizontal surface such as a table top "
        "grazed by beams; and so is a thin object whose own mission continues its surface (points within 2 cm of its "
        "median height in at least half of the 0.1 m columns of a box_margin-wide strip along a side) on at least "
        "thin_surface_sides of its four sides: a patch of a shelf or table top the other mission's beams grazed "
        "without hitting it (a sparse scanner), where a thing that moved stands free (a cart's deck) or continues "
        "on one side only (the sliver of a table top moved a little). An object moved by less than its own size keeps occupying the overlap of its two poses, so "
        "the volumetric difference finds only slivers of it. For consecutive missions, clusters whose "
        "boxes are at most pair_gap apart are paired (nearest first, each in at most one completed pair; with "
        "pair_retry a refused pair frees both for their next candidates; among touching boxes the nearer centroids first); each grows "
        "through its own mission's full cloud (breadth-first over occupied voxels of edge `voxel`, "
        "inside the pair's union box grown by box_margin, above the local floor clearance, "
        "never into another object's points). Where a growth finds more "
        "than max_leak occupied voxels just outside the region per voxel it grew into (it touches a wall or "
        "furniture), both grow again inside the union of the two boxes without margin (leak_growth = own_box; "
        "base: the pair is left alone). The growth is kept only if both grown objects have the "
        "shape of one rigid object (height above the floor and footprint-rectangle sides agree "
        "within max(shape_tolerance x the larger, shape_slack)) and, with still_check, the two grown objects "
        "registered onto each other (lista::objreg's ICP from yaw turns) must fit better moved than where they "
        "stand, else they grew into a static thing between two changes. With join_fragments, other objects of a pair "
        "member's mission that its growth reaches are tried in the pair too (a turned short move leaves slivers "
        "at both ends) and joined into it if the shapes then agree within half that allowance. With "
        "join_connected, two objects of one mission that no completed pair holds, boxes at most pair_gap apart and "
        "voxels not touching, are joined when a growth from one inside the union of their boxes grown by "
        "box_margin (no leak check: a table's top reaches past its legs' boxes) reaches the other over points it "
        "adds of which at most 1 - static_share lie where every neighbouring mission holds points too: the "
        "material between them changed with them (a "
        "removed table's top between the legs the difference found). Then, with self_complete, every object "
        "grows the same way inside its own box grown by box_margin, down to the floor if it stands "
        "on it (the difference cannot confirm change next to the floor, so objects lose their base); "
        "if that growth wants out of the box (it touches a wall or furniture), it is cut to the object's own box "
        "and the base below its lowest part is added (leak_growth = base: the base only). With "
        "static_check, when at least static_share of what a self-completion would add lies in voxels "
        "every neighbouring mission also holds above its own local floor, those points are left out: "
        "they did not change (a sliver of phantom change on a static wall stays a sliver; below the "
        "share the growth is kept, as a short move overlaps its other pose). The local "
        "floor is found around each object; points within max(floor_clearance, 4 sigma of the "
        "floor's noise) of it are never added. Every object standing on its local floor (lowest point at most "
        "0.3 m above it) gets that floor's height as its floor_z, which describe.learned measures heights "
        "from. Last, an object with at least nested_share of its points inside the box of a larger object of the same "
        "mission (grown by half a voxel) joins it: growth never takes another object's points, so one object cut "
        "in two by the difference stays two clusters interleaved in one box. Ids and order are kept, except that "
        "when any object is dropped (floor, unchanged thin surface) or joins another the ids are renumbered 0..n-1.";
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
    Outputs out;
    out.put("objects", std::move(objects));
    return out;
  }

 private:
  CompletionConfig c_;
};

const ParamTable<CompleteStageConfig>& param_table() {
  using C = CompleteStageConfig;
  static const ParamTable<C> table = [] {
    ParamTable<C> t;
    t.bind("voxel", &C::voxel, "connectivity grid of the growth").range(0.01, 1).unit("m");
    t.bind("pair_gap", &C::pair_gap, "largest box-to-box gap of a pair").range(0, 10).unit("m");
    t.bind("box_margin", &C::box_margin, "growth region: union box of the pair grown by this").range(0, 2).unit("m");
    t.bind("floor_clearance", &C::floor_clearance, "least height above the local floor of an added point (4 sigma of the floor's noise if more)").range(0, 1).unit("m");
    t.bind("floor_percentile", &C::floor_percentile, "of the per-cell lowest points, the local floor").range(0, 1);
    t.bind("shape_tolerance", &C::shape_tolerance, "relative disagreement of the pair's extents allowed").range(0, 2);
    t.bind("shape_slack", &C::shape_slack, "absolute disagreement of the pair's extents allowed").range(0, 2).unit("m");
    t.bind("leak_growth", &C::leak_growth,
           "what a growth that leaks out of its region (the object touches a wall or furniture) keeps: "
           "own_box = a self-completion what it reaches inside the object's own box, and its base; a "
           "short-move pair what it reaches inside the union of its two boxes (shapes must agree); "
           "base = a self-completion only the base below its lowest part, a pair nothing")
        .one_of({"own_box", "base"});
    t.bind("self_complete", &C::self_complete, "also complete every object inside its own box grown by box_margin (its base, mostly)");
    t.bind("static_check", &C::static_check,
           "self-completion leaves out points every neighbouring mission also holds (see static_share)");
    // Shares of points: fractions in [0, 1].
    t.bind("static_share", &C::static_share,
           "share of a self-completion held unchanged by every neighbouring mission from which on those points "
           "are left out; also the share that makes a thin object an unchanged surface (thin_height), and 1 - it "
           "the most of join_connected's connecting points that may be held there")
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
    t.bind("pair_order", &C::pair_order,
           "order in which candidate pairs are tried: by box gap in whole voxels (a gap under one "
           "voxel touches the growth as an overlap does), then by the horizontal distance of their "
           "centroids (centroid); or by gap, then object id (gap)")
        .one_of({"centroid", "gap"});
    t.bind("join_fragments", &C::join_fragments,
           "a pair's growth that reaches other objects of its own mission (within one voxel) that no "
           "completed pair holds grows again with them joined; kept, and they are joined into the "
           "pair's object, if the shapes then agree (a turned short move leaves slivers at both ends)");
    t.bind("still_check", &C::still_check,
           "refuse a pair whose two grown objects fit best where they stand: registered onto each "
           "other, the pose moves them under 5 cm and 5 degrees, or they fit better unmoved than at "
           "that pose (a cabinet between a box taken away and a barrel put down is no short move)");
    t.bind("join_connected", &C::join_connected,
           "two objects of one mission that no completed pair holds are joined when a growth from one "
           "reaches the other over points mostly not held by the neighbouring missions (a table's "
           "legs without its top)");
    t.bind("max_leak", &C::max_leak, "occupied voxels found just outside the region, per voxel grown into, at most").range(0, 1);
    return t;
  }();
  return table;
}

void register_stages(Registrar& r) {
  r.add(CompleteStage::info(), [](const Params& p) { return std::make_unique<CompleteStage>(p); });
}

}  // namespace
}  // namespace lista::seg

LISTA_PLUGIN(lista::seg::register_stages)
