// Parameters shared by every volumetric backend: declared once here so that
// `volumetric.octomap` and `volumetric.openvdb` are swappable by changing one
// line of a pipeline.
#pragma once

#include <lista/params.hpp>

#include <vector>

namespace lista::raycast {

struct VolumetricConfig {
  double resolution = 0.05;          // voxel edge, m
  double max_range = 30.0;           // m; <= 0: unlimited
  double prob_hit = 0.7;             // P(occupied | return in voxel)
  double prob_miss = 0.4;            // P(occupied | beam passed through)
  double clamping_min = 0.1192;      // probability bounds of a voxel
  double clamping_max = 0.971;
  double occupied_threshold = 0.5;   // P above which a voxel is occupied
  // P(this) - P(other) above which a voxel changed. 0.35: at least three
  // updates in all, one in each mission (one hit against two misses: 0.70 -
  // 0.31; two hits against one miss: 0.85 - 0.40; one of each, 0.30, is not
  // enough). The paper's 0.5 asks four to five, which sparse sensors and
  // short missions rarely give a voxel (docs/volumetric.md).
  double change_threshold = 0.35;
  // True when the pipeline gave change_threshold: it then holds for every
  // pair of missions, even one whose scan counts cannot pass it. Otherwise
  // such a pair (one scan each) takes one hit against one miss as change.
  bool change_threshold_given = false;
  int neighbourhood = 1;             // voxels: other mission must be clear around the point
  double hit_margin = 0.25;          // m of each beam before its return not carved free
  // A beam going down ends its free part where it is graze_height above its
  // return's height (graze_height / sin(descent) short of the return), at
  // most graze_max: a far floor return's beam runs within one voxel of the
  // floor for metres, and would otherwise clear floor voxels the other
  // mission holds. 0 = off (the default: on fresh sets it lost as much
  // recall near floors as it removed phantom floor change; docs/volumetric.md).
  double graze_height = 0.0;         // m
  double graze_max = 2.0;            // m
};

// The declarations, defaults equal to VolumetricConfig's.
std::vector<ParamSpec> volumetric_params();

// Reads and cross-checks the values (prob_hit > 0.5 > prob_miss,
// clamping_min < clamping_max); throws lista::Error with a one-line reason.
VolumetricConfig volumetric_config(const Params& params);
void validate(const VolumetricConfig& config);

}  // namespace lista::raycast
