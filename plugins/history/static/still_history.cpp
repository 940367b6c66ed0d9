#include "still_history.hpp"

#include <lista/error.hpp>
#include <lista/parallel.hpp>
#include <lista_geometry/radius_grid.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>

namespace lista::history {

namespace {

struct Box {
  Eigen::Vector3f lo, hi;
  bool contains(const Eigen::Vector3f& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
};

// A mission's points near the changed objects (common frame), hashed.
struct Cloud {
  PointSet points;
  geometry::RadiusGrid grid;
  explicit Cloud(float r) : grid(r) {}
  void add(const PointSet& from, size_t i, const Eigen::Vector3f& p) {
    points.push_back_from(from, i);
    points.xyz.back() = p;
    grid.add(p, uint32_t(points.size() - 1));
  }
};

// Every point of `mission` inside any of `boxes`, in scan then file order.
PointSet gather(const Mission& mission, const std::vector<Box>& boxes, int threads) {
  const size_t n = mission.scans.size();
  std::vector<PointSet> per_scan(n);
  if (boxes.empty()) return {};
  Box all = boxes.front();
  for (const Box& b : boxes) all.lo = all.lo.cwiseMin(b.lo), all.hi = all.hi.cwiseMax(b.hi);
  parallel_for(n, threads, [&](size_t s) {
    const Scan& scan = mission.scans[s];
    if (!scan.points) return;
    const Eigen::Affine3f T = mission.sensor_to_common(s).cast<float>();
    const PointSet& src = *scan.points;
    for (size_t i = 0; i < src.size(); ++i) {
      const Eigen::Vector3f p = T * src.xyz[i];
      if (!all.contains(p)) continue;
      for (const Box& b : boxes)
        if (b.contains(p)) {
          per_scan[s].push_back_from(src, i);
          per_scan[s].xyz.back() = p;
          break;
        }
    }
  });
  PointSet out;
  for (const PointSet& s : per_scan) out.append(s);
  return out;
}

// At most about 2000 of an object's points, evenly spread over its list.
std::vector<Eigen::Vector3f> sample(const PointSet& p) {
  const size_t step = std::max<size_t>(1, p.size() / 2000);
  std::vector<Eigen::Vector3f> out;
  for (size_t i = 0; i < p.size(); i += step) out.push_back(p.xyz[i]);
  return out;
}

double share_near(const std::vector<Eigen::Vector3f>& probe, const Cloud& cloud) {
  if (probe.empty()) return 0.0;
  size_t hit = 0;
  for (const auto& p : probe) hit += cloud.grid.any_near(cloud.points.xyz, p);
  return double(hit) / double(probe.size());
}

// The points of `cloud` that show `object` again: those within the radius
// of its points, then those connected to them (within the radius) inside
// its box grown by the radius; none below its lowest point (segmentation
// kept the floor, and its noise, below that). The growth takes no point
// that `absent` (the mission where the object was not at this place) also
// shows: a wall or floor the object touches is there without it, and
// growing into it took in structure (a shelf against a wall, three times
// its own points). The first points are exempt: near the object's own, they
// keep its foot, which lies within the radius of the floor.
PointSet take(const Object& object, const Cloud& cloud, float radius, const Cloud* absent) {
  const float floor_z = object.bbox_min.z();
  const Box box{object.bbox_min.array() - radius, object.bbox_max.array() + radius};
  // 0: not looked at, 1: taken, 2: refused (structure).
  std::vector<char> state(cloud.points.size(), 0);
  std::deque<uint32_t> queue;
  auto consider = [&](uint32_t i, bool grown) {
    if (state[i]) return;
    const Eigen::Vector3f& q = cloud.points.xyz[i];
    if (q.z() < floor_z) return;
    if (grown && absent && absent->grid.any_near(absent->points.xyz, q)) {
      state[i] = 2;
      return;
    }
    state[i] = 1;
    queue.push_back(i);
  };
  for (const auto& p : object.points.xyz)
    cloud.grid.for_near(cloud.points.xyz, p, [&](uint32_t i) { consider(i, false); });
  while (!queue.empty()) {
    const uint32_t i = queue.front();
    queue.pop_front();
    cloud.grid.for_near(cloud.points.xyz, cloud.points.xyz[i], [&](uint32_t j) {
      if (box.contains(cloud.points.xyz[j])) consider(j, true);
    });
  }
  std::vector<uint32_t> idx;
  for (uint32_t i = 0; i < state.size(); ++i)
    if (state[i] == 1) idx.push_back(i);
  return cloud.points.select(idx);
}

// The mission an object changed against (its other pose or its absence), and
// the direction (+1 next, -1 previous) in which it may have stood still.
struct Direction {
  int step = 0;           // 0: none
  int changed_against = -1;
};

Direction direction_of(const Object& o, const ObjectChange& c, const ObjectSet& objects, size_t n_missions) {
  const int k = int(o.mission);
  Direction d;
  if (c.status == ChangeStatus::added) d = {+1, k - 1};
  else if (c.status == ChangeStatus::removed) d = {-1, k + 1};
  else if (const Object* partner = objects.find(c.match)) {
    const int pm = int(partner->mission);
    if (pm < k) d = {+1, pm};
    else if (pm > k) d = {-1, pm};
  }
  const int next = k + d.step;
  if (d.step == 0 || next < 0 || next >= int(n_missions)) return {};
  if (d.changed_against < 0 || d.changed_against >= int(n_missions)) d.changed_against = -1;
  return d;
}

}  // namespace

StillResult extend_histories(const MissionSet& missions, const ObjectSet& objects, const Matches& matches,
                             const Groups* groups, const StillConfig& cfg, int threads) {
  StillResult out;
  out.objects = objects;
  out.matches = matches;
  if (groups) out.groups = *groups;
  const size_t nm = objects.missions.size();
  if (nm < 2 || objects.objects.empty()) return out;

  std::vector<const Mission*> mission_of(nm);
  for (size_t m = 0; m < nm; ++m) {
    mission_of[m] = missions.find(objects.missions[m]);
    if (!mission_of[m])
      throw Error("objects input names mission '" + objects.missions[m] + "', which the missions input lacks");
  }

  // A still object occupies the place it had, so each mission is read once,
  // around every object of every mission.
  const float r = float(cfg.radius);
  std::vector<Box> boxes;
  for (const Object& o : objects.objects)
    boxes.push_back({o.bbox_min.array() - 2.f * r, o.bbox_max.array() + 2.f * r});
  std::vector<Cloud> clouds(nm, Cloud(r)), reported(nm, Cloud(r));
  for (size_t m = 0; m < nm; ++m) {
    const PointSet pts = gather(*mission_of[m], boxes, threads);
    for (size_t i = 0; i < pts.size(); ++i) clouds[m].add(pts, i, pts.xyz[i]);
  }
  for (const Object& o : objects.objects)
    for (size_t i = 0; i < o.points.size(); ++i) reported[o.mission].add(o.points, i, o.points.xyz[i]);

  int next_id = 0;
  for (const Object& o : objects.objects) next_id = std::max(next_id, o.id + 1);

  const size_t n_in = objects.objects.size();
  for (size_t oi = 0; oi < n_in; ++oi) {
    // From out.matches: an earlier object of the same history may have
    // extended it already (a move in the middle, followed both ways).
    const ObjectChange* c0 = out.matches.find(objects.objects[oi].id);
    if (!c0) continue;
    const ObjectChange source = *c0;  // copied: out.matches grows below
    const Direction dir = direction_of(objects.objects[oi], source, objects, nm);
    if (dir.step == 0) continue;
    std::vector<int> chain = source.history.empty() ? std::vector<int>{source.object_id} : source.history;
    std::vector<uint32_t> chain_missions;
    for (int id : chain)
      if (const Object* m = out.objects.find(id)) chain_missions.push_back(m->mission);

    // Walks from the object `step` missions at a time while it stands still,
    // adding a copy to each mission. On the first step its share there must
    // exceed `reference` (its share on the other side, where it changed) by
    // min_share_gap: a static thing wrongly flagged shows alike on both sides.
    // `status`: the copies' status; a move's copies keep its partner.
    const std::vector<Eigen::Vector3f> probe0 = sample(objects.objects[oi].points);
    auto walk = [&](int step, double reference, ChangeStatus status, int absent) {
      size_t made = 0;
      Object current = objects.objects[oi];
      std::vector<Eigen::Vector3f> probe = probe0;
      bool first = true;
      for (int m = int(current.mission) + step; m >= 0 && m < int(nm); m += step) {
        if (std::find(chain_missions.begin(), chain_missions.end(), uint32_t(m)) != chain_missions.end()) break;
        StillCandidate cand;
        cand.source = current.id;
        cand.mission = uint32_t(m);
        cand.gone_share = first ? reference : -1.0;
        cand.reported_share = share_near(probe, reported[m]);
        cand.still_share = share_near(probe, clouds[m]);
        const bool changed = cand.still_share < cfg.min_still_share ||
                             (first && reference >= 0.0 && cand.still_share - reference < cfg.min_share_gap);
        if (cand.reported_share > cfg.max_reported_share) cand.verdict = "reported";
        else if (changed) cand.verdict = "changed";
        Object copy;
        if (cand.verdict.empty()) {
          copy.points = take(current, clouds[m], r, absent >= 0 ? &clouds[absent] : nullptr);
          if (copy.points.empty()) cand.verdict = "no points";
        }
        if (!cand.verdict.empty()) {
          out.candidates.push_back(cand);
          return made;
        }
        cand.verdict = status == source.status ? "still" : "still, " + std::string(to_string(status));
        copy.id = next_id++;
        copy.mission = uint32_t(m);
        // Nothing changed against either neighbour here: it stood still.
        copy.points.changed_against.assign(copy.points.size(), 0);
        copy.floor_z = current.floor_z;
        copy.update_geometry();
        for (size_t i = 0; i < copy.points.size(); ++i) reported[m].add(copy.points, i, copy.points.xyz[i]);
        cand.copy = copy.id;
        out.candidates.push_back(cand);

        ObjectChange c;
        c.object_id = copy.id;
        c.status = status;
        c.confidence = std::min(source.confidence, cand.still_share);
        if (status == ChangeStatus::moved) {
          // Still since (or until) the move: the same partner, the same motion.
          c.match = source.match;
          c.cost = source.cost;
          c.has_transform = source.has_transform;
          c.transform = source.transform;
          c.alternative_transforms = source.alternative_transforms;
        }
        out.matches.objects.push_back(c);
        if (groups) {
          for (size_t g = 0; g < groups->object_ids.size(); ++g)
            if (groups->object_ids[g] == source.object_id) {
              out.groups.object_ids.push_back(copy.id);
              out.groups.group.push_back(groups->group[g]);
              if (g < groups->confidence.size()) out.groups.confidence.push_back(groups->confidence[g]);
              break;
            }
        }
        chain.push_back(copy.id);
        chain_missions.push_back(copy.mission);
        ++out.copies;
        probe = sample(copy.points);
        current = copy;
        out.objects.objects.push_back(std::move(copy));
        first = false;
        ++made;
      }
      return made;
    };

    // Away from the change, against the object's share where it changed.
    const double there = dir.changed_against >= 0 ? share_near(probe0, clouds[dir.changed_against]) : -1.0;
    walk(dir.step, there, source.status, dir.changed_against);

    // Toward it: an added or removed object that stands still in the
    // mission it reportedly changed against, and is gone from its place on
    // the other side, changed against that side instead: its status was
    // wrong. It and its copies take the status the two sides show: still in
    // later missions and gone from an earlier one is added; the reverse,
    // removed. (A move's partner stands in that mission; that contradiction
    // is left alone.)
    const int k = int(objects.objects[oi].mission);
    if (cfg.follow_contradictions && source.status != ChangeStatus::moved && dir.changed_against == k - dir.step &&
        there >= cfg.min_still_share) {
      const double other_side = share_near(probe0, clouds[k + dir.step]);
      const ChangeStatus shown = -dir.step > 0 ? ChangeStatus::added : ChangeStatus::removed;
      if (there - other_side >= cfg.min_share_gap && walk(-dir.step, other_side, shown, k + dir.step) > 0) {
        out.matches.find(source.object_id)->status = shown;
        out.corrected.push_back(source.object_id);
      }
    }

    // Every member of the history lists the whole history, in mission order.
    if (chain.size() > (source.history.empty() ? 1u : source.history.size())) {
      std::map<int, uint32_t> mission_of_id;
      for (int id : chain) mission_of_id[id] = out.objects.find(id)->mission;
      std::sort(chain.begin(), chain.end(), [&](int a, int b) {
        return mission_of_id[a] != mission_of_id[b] ? mission_of_id[a] < mission_of_id[b] : a < b;
      });
      for (int id : chain)
        if (ObjectChange* c = out.matches.find(id)) c->history = chain;
    }
  }
  return out;
}

}  // namespace lista::history
