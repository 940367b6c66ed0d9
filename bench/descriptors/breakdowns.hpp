// Where a descriptor misses: top-1 split by what each view is (its point
// count, the sensor that took it, its distance, which part of the object
// it shows). Each breakdown puts every view in one named bin, or in none
// when the views folder does not say (synthetic views carry no sensor).
#pragma once

#include <lista_objfeat/views.hpp>

#include <string>
#include <vector>

namespace lista::bench {

struct Breakdown {
  std::string title;     // table heading, e.g. "top-1 by sensor"
  std::string json_key;  // e.g. "top1_by_sensor"
  std::vector<std::string> bins;
  std::vector<int> bin_of;  // per view: index into bins, -1 = in none
  bool empty() const;       // no view in any bin
};

// Points in the view: 0-64, 65-299, 300-1499, >= 1500.
Breakdown by_view_size(const objfeat::ViewSet& views);
// index.json "sensor", bins in name order.
Breakdown by_sensor(const objfeat::ViewSet& views);
// index.json "distance" (sensor to object, m): 0-3, 3-5, 5-8, 8-12, >= 12.
Breakdown by_distance(const objfeat::ViewSet& views);
// Which part of the object the view shows, against its shape's height
// (views stand on z = 0, docs/datasets.md): "bottom missed" when the
// lowest point lies over 10 % of the height + 5 cm above the floor (the
// sensor's lowest beam passed over the base), "top missed" when the highest
// lies over that below the top, "both", else "whole".
Breakdown by_coverage(const objfeat::ViewSet& views);

struct BinScore {
  size_t views = 0, hits = 0;
  double top1() const { return views ? double(hits) / double(views) : 0.0; }
};
// Per bin, how many views and how many of them found their own shape first
// (`top1_hits`: objfeat::RetrievalScores, one per view; views whose shape
// has no other view, -1 there, are left out as top-1 leaves them out).
std::vector<BinScore> score_bins(const Breakdown& b, const std::vector<int>& top1_hits);

}  // namespace lista::bench
