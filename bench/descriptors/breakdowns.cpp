#include "breakdowns.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace lista::bench {

bool Breakdown::empty() const {
  return std::all_of(bin_of.begin(), bin_of.end(), [](int b) { return b < 0; });
}

namespace {

// Bins [edges[k], edges[k + 1]) named "a-b", the last one ">= a".
Breakdown by_edges(const objfeat::ViewSet& views, const std::string& title, const std::string& json_key,
                   const std::vector<double>& edges, double (*value)(const objfeat::View&)) {
  auto text = [](double x) {  // 12, 2.5: no trailing zeros
    std::string s = std::to_string(x);
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
    return s;
  };
  Breakdown b{title, json_key, {}, {}};
  for (size_t k = 0; k < edges.size(); ++k)
    b.bins.push_back(k + 1 < edges.size() ? text(edges[k]) + "-" + text(edges[k + 1]) : ">= " + text(edges[k]));
  for (const auto& v : views.views) {
    const double x = value(v);
    int bin = -1;
    if (std::isfinite(x))
      for (size_t k = 0; k < edges.size(); ++k)
        if (x >= edges[k]) bin = int(k);
    b.bin_of.push_back(bin);
  }
  return b;
}

}  // namespace

Breakdown by_view_size(const objfeat::ViewSet& views) {
  Breakdown b = by_edges(views, "top-1 by view size (points)", "top1_by_view_size", {0, 65, 300, 1500},
                         [](const objfeat::View& v) { return double(v.points.xyz.size()); });
  b.bins = {"0-64", "65-299", "300-1499", ">= 1500"};  // counts, so closed ranges
  return b;
}

Breakdown by_sensor(const objfeat::ViewSet& views) {
  Breakdown b{"top-1 by sensor", "top1_by_sensor", {}, {}};
  std::set<std::string> names;
  for (const auto& v : views.views)
    if (!v.sensor.empty()) names.insert(v.sensor);
  b.bins.assign(names.begin(), names.end());
  for (const auto& v : views.views)
    b.bin_of.push_back(v.sensor.empty() ? -1 : int(std::find(b.bins.begin(), b.bins.end(), v.sensor) - b.bins.begin()));
  return b;
}

Breakdown by_distance(const objfeat::ViewSet& views) {
  return by_edges(views, "top-1 by distance (m)", "top1_by_distance", {0, 3, 5, 8, 12},
                  [](const objfeat::View& v) { return double(v.distance); });
}

Breakdown by_coverage(const objfeat::ViewSet& views) {
  Breakdown b{"top-1 by what the view shows", "top1_by_coverage", {"whole", "bottom missed", "top missed", "both missed"}, {}};
  for (const auto& v : views.views) {
    const float height = v.extent[2];
    if (!std::isfinite(height) || v.points.xyz.empty()) {
      b.bin_of.push_back(-1);
      continue;
    }
    float lo = v.points.xyz[0].z(), hi = lo;
    for (const auto& p : v.points.xyz) lo = std::min(lo, p.z()), hi = std::max(hi, p.z());
    const float slack = 0.1f * height + 0.05f;
    const bool bottom = lo > slack, top = hi < height - slack;
    b.bin_of.push_back(bottom && top ? 3 : top ? 2 : bottom ? 1 : 0);
  }
  return b;
}

std::vector<BinScore> score_bins(const Breakdown& b, const std::vector<int>& top1_hits) {
  std::vector<BinScore> out(b.bins.size());
  for (size_t i = 0; i < b.bin_of.size() && i < top1_hits.size(); ++i)
    if (b.bin_of[i] >= 0 && top1_hits[i] >= 0) {  // a view alone with its shape is no query
      ++out[size_t(b.bin_of[i])].views;
      out[size_t(b.bin_of[i])].hits += size_t(top1_hits[i] != 0);
    }
  return out;
}

}  // namespace lista::bench
