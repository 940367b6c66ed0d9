#include "observability.hpp"

#include <lista/error.hpp>
#include <lista/parallel.hpp>
#include <lista_bench/truth_score.hpp>
#include <lista_geometry/range_image.hpp>

#include <algorithm>
#include <map>
#include <memory>
#include <set>

namespace {

using lista::geometry::RangeImage;

enum class Seen : uint8_t { nothing, present, empty };

struct MissionImages {
  std::vector<std::unique_ptr<RangeImage>> images;  // per scan, sensor frame
  std::vector<double> reach;                        // per scan: its farthest return
};

MissionImages images_of(const lista::Mission& m, int threads) {
  MissionImages out;
  out.images.resize(m.scans.size());
  out.reach.assign(m.scans.size(), 0.0);
  lista::parallel_for(m.scans.size(), threads, [&](size_t s) {
    if (!m.scans[s].points) return;
    out.images[s] = std::make_unique<RangeImage>(*m.scans[s].points);
    for (const auto& p : m.scans[s].points->xyz) out.reach[s] = std::max(out.reach[s], double(p.norm()));
  });
  return out;
}

// What mission `other`'s scans saw at world point w: empty wins over present.
Seen seen_by(const lista::Mission& other, const MissionImages& images, const Eigen::Vector3d& w,
             const ObservabilityOptions& o) {
  Seen best = Seen::nothing;
  for (size_t t = 0; t < other.scans.size(); ++t) {
    if (!images.images[t]) continue;
    const Eigen::Vector3d q = other.poses_gt[t].inverse() * w;
    if (q.norm() > images.reach[t] + o.margin) continue;
    switch (images.images[t]->look(q, q.normalized(), 0.0, o.rho, o.margin)) {
      case RangeImage::Vote::see_through: return Seen::empty;
      case RangeImage::Vote::present: best = Seen::present; break;
      case RangeImage::Vote::none: break;
    }
  }
  return best;
}

}  // namespace

std::vector<MissionObservability> observability(const lista::MissionSet& missions,
                                                const lista::io::GroundTruth& truth,
                                                const ObservabilityOptions& o) {
  const auto& all = missions.missions;
  for (const auto& m : all)
    if (m.poses_gt.size() != m.scans.size())
      throw lista::Error("mission '" + m.name + "' has no poses_gt.txt with one pose per scan: give the true poses");
  std::vector<MissionImages> images;
  for (const auto& m : all) images.push_back(images_of(m, o.threads));
  const std::set<uint32_t> dynamic = dynamic_objects(truth);
  std::vector<MissionObservability> rows;
  for (size_t m = 0; m < all.size(); ++m) {
    // The neighbours this mission's change is judged against, each with the objects it changed.
    std::vector<std::pair<size_t, std::set<uint32_t>>> neighbours;
    if (m > 0) neighbours.push_back({m - 1, objects_changed_between(truth, all[m - 1].name, all[m].name)});
    if (m + 1 < all.size()) neighbours.push_back({m + 1, objects_changed_between(truth, all[m].name, all[m + 1].name)});
    MissionObservability row;
    row.mission = all[m].name;
    std::map<uint32_t, ObjectObservability> per_object;  // by label
    for (size_t s = 0; s < all[m].scans.size(); ++s) {
      const lista::PointSet* p = all[m].scans[s].points.get();
      if (!p || !p->has_label()) continue;
      std::vector<Seen> seen(p->size(), Seen::nothing);
      std::vector<uint8_t> changed(p->size(), 0);
      lista::parallel_for(p->size(), o.threads, [&](size_t j) {
        const uint32_t label = p->label[j];
        if (label == 0 || dynamic.count(label)) return;
        const Eigen::Vector3d w = all[m].poses_gt[s] * p->xyz[j].cast<double>();
        for (const auto& [k, ids] : neighbours) {
          if (!ids.count(label)) continue;
          changed[j] = 1;
          seen[j] = std::max(seen[j], seen_by(all[k], images[k], w, o));
          if (seen[j] == Seen::empty) break;
        }
      });
      for (size_t j = 0; j < p->size(); ++j) {
        if (!changed[j]) continue;
        ObjectObservability& object = per_object[p->label[j]];
        object.id = p->label[j];
        ++object.changed;
        object.seen_empty += seen[j] == Seen::empty;
        object.seen_present += seen[j] == Seen::present;
      }
    }
    for (const auto& [label, object] : per_object) {
      row.changed += object.changed;
      row.seen_empty += object.seen_empty;
      row.seen_present += object.seen_present;
      if (object.seen_empty >= uint64_t(o.min_evidence)) row.in_visible_objects += object.changed;
      row.objects.push_back(object);
    }
    rows.push_back(row);
  }
  return rows;
}
