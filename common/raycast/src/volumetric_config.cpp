#include <lista/param_table.hpp>
#include <lista_raycast/volumetric_config.hpp>

namespace lista::raycast {

namespace {

const ParamTable<VolumetricConfig>& param_table() {
  using C = VolumetricConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("resolution", &C::resolution, "voxel edge length").range(0.005, 5.0).unit("m");
    // The bound also refuses NaN and inf (ParamSpec::check): without one, NaN
    // passed validation, ran as "unlimited" and the report recorded nan.
    t.bind("max_range", &C::max_range,
           "beams are cut at this range: a farther return adds free space up to the "
           "range and no hit (far beams are wider than a voxel); 0 means unlimited")
        .at_least(0.0)
        .unit("m");
    t.bind("prob_hit", &C::prob_hit, "occupancy probability of a voxel holding a return").range(0.5, 1.0);
    t.bind("prob_miss", &C::prob_miss,
           "occupancy probability of a voxel a beam passed through; closer to 0.5 than "
           "prob_hit so a single grazing beam cannot clear a surface seen by other scans")
        .range(0.0, 0.5);
    t.bind("clamping_min", &C::clamping_min, "lower probability bound of a voxel").range(0.0, 1.0);
    t.bind("clamping_max", &C::clamping_max, "upper probability bound of a voxel").range(0.0, 1.0);
    t.bind("occupied_threshold", &C::occupied_threshold, "probability above which a voxel counts as occupied")
        .range(0.0, 1.0);
    t.bind("change_threshold", &C::change_threshold,
           "a point's voxel changed when its occupancy probability exceeds that in a neighbouring mission by more than this (0.35: three updates in all, at least one in each mission)")
        .range(0.0, 1.0);
    t.bind("neighbourhood", &C::neighbourhood,
           "radius in voxels (Chebyshev) that must hold no occupied voxel in the other mission; 0 compares the point's voxel only; a pair (or a stretch of it) whose measured misfit needs more gets more")
        .range(0, 3)
        .unit("voxels");
    t.bind("hit_margin", &C::hit_margin,
           "stretch of each beam before its return that is not marked free, so a grazing beam does not clear the surface it hits")
        .range(0.0, 1.0)
        .unit("m");
    t.bind("graze_height", &C::graze_height,
           "a descending beam is not marked free where it runs within this height above its return (at most graze_max before it); 0 = off (0.05 for outdoor ground)")
        .range(0.0, 1.0)
        .unit("m");
    t.bind("graze_max", &C::graze_max, "longest stretch before a return that graze_height keeps from being marked free")
        .range(0.0, 10.0)
        .unit("m");
  });
}

}  // namespace

std::vector<ParamSpec> volumetric_params() { return param_table().specs(); }

void validate(const VolumetricConfig& c) {
  if (!(c.prob_hit > 0.5 && c.prob_hit < 1.0))
    throw Error("prob_hit must be in (0.5, 1), got " + to_string(ParamValue(c.prob_hit)));
  if (!(c.prob_miss > 0.0 && c.prob_miss < 0.5))
    throw Error("prob_miss must be in (0, 0.5), got " + to_string(ParamValue(c.prob_miss)));
  if (!(c.clamping_min > 0.0 && c.clamping_min < c.clamping_max && c.clamping_max < 1.0))
    throw Error("clamping must satisfy 0 < clamping_min < clamping_max < 1, got " +
                to_string(ParamValue(c.clamping_min)) + " and " + to_string(ParamValue(c.clamping_max)));
  if (!(c.resolution > 0)) throw Error("resolution must be > 0");
  if (c.neighbourhood < 0) throw Error("neighbourhood must be >= 0");
  if (c.hit_margin < 0) throw Error("hit_margin must be >= 0");
  if (c.graze_height < 0 || c.graze_max < 0) throw Error("graze_height and graze_max must be >= 0");
}

VolumetricConfig volumetric_config(const Params& p) {
  VolumetricConfig c = param_table().read(p);
  c.change_threshold_given = p.is_set("change_threshold");
  validate(c);
  return c;
}

}  // namespace lista::raycast
