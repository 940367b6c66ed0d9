#include "still_history.hpp"

#include "mission_cloud.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <map>

namespace lista::history {

namespace {

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

// One run of extend_histories: the missions' clouds, the copies made so far
// and the ids they take. Objects are followed one at a time, in input order.
class StillFollower {
 public:
  StillFollower(const ObjectSet& objects, const Groups* groups, const StillConfig& cfg, std::vector<Cloud> clouds,
                std::vector<Cloud> reported, StillResult& out)
      : objects_(objects),
        groups_(groups),
        cfg_(cfg),
        radius_(float(cfg.radius)),
        nm_(objects.missions.size()),
        clouds_(std::move(clouds)),
        reported_(std::move(reported)),
        out_(out) {
    for (const Object& o : objects.objects) next_id_ = std::max(next_id_, o.id + 1);
  }

  void follow(size_t oi);

 private:
  // One object's history being extended.
  struct Followed {
    size_t index;        // in objects.objects
    ObjectChange source;  // its change as it came (copied: out_.matches grows)
    std::vector<int> chain;  // the history's ids
    std::vector<uint32_t> chain_missions;
    std::vector<Eigen::Vector3f> probe0;  // a sample of its points
  };

  size_t walk(Followed& f, int step, double reference, ChangeStatus status, int absent);
  void add_copy(Followed& f, Object& copy, StillCandidate& cand, ChangeStatus status);

  const ObjectSet& objects_;
  const Groups* groups_;
  const StillConfig& cfg_;
  const float radius_;
  const size_t nm_;
  std::vector<Cloud> clouds_, reported_;
  StillResult& out_;
  int next_id_ = 0;
};

// Walks from the object `step` missions at a time while it stands still,
// adding a copy to each mission. On the first step its share there must
// exceed `reference` (its share on the other side, where it changed) by
// min_share_gap: a static thing wrongly flagged shows alike on both sides.
// `status`: the copies' status; a move's copies keep its partner. Returns
// the copies made.
size_t StillFollower::walk(Followed& f, int step, double reference, ChangeStatus status, int absent) {
  size_t made = 0;
  Object current = objects_.objects[f.index];
  std::vector<Eigen::Vector3f> probe = f.probe0;
  bool first = true;
  for (int m = int(current.mission) + step; m >= 0 && m < int(nm_); m += step) {
    if (std::find(f.chain_missions.begin(), f.chain_missions.end(), uint32_t(m)) != f.chain_missions.end()) break;
    StillCandidate cand;
    cand.source = current.id;
    cand.mission = uint32_t(m);
    cand.gone_share = first ? reference : -1.0;
    cand.reported_share = share_near(probe, reported_[m]);
    cand.still_share = share_near(probe, clouds_[m]);
    const bool changed = cand.still_share < cfg_.min_still_share ||
                         (first && reference >= 0.0 && cand.still_share - reference < cfg_.min_share_gap);
    if (cand.reported_share > cfg_.max_reported_share) cand.verdict = "reported";
    else if (changed) cand.verdict = "changed";
    Object copy;
    if (cand.verdict.empty()) {
      copy.points = take(current, clouds_[m], radius_, absent >= 0 ? &clouds_[absent] : nullptr);
      if (copy.points.empty()) cand.verdict = "no points";
    }
    if (!cand.verdict.empty()) {
      out_.candidates.push_back(cand);
      return made;
    }
    copy.mission = uint32_t(m);
    copy.floor_z = current.floor_z;
    add_copy(f, copy, cand, status);
    probe = sample(copy.points);
    current = copy;
    out_.objects.objects.push_back(std::move(copy));
    first = false;
    ++made;
  }
  return made;
}

// A copy of f's object found standing still in copy.mission: its id, its
// change (a move's copy keeps the partner and motion) and group, and its
// place in the history.
void StillFollower::add_copy(Followed& f, Object& copy, StillCandidate& cand, ChangeStatus status) {
  const ObjectChange& source = f.source;
  const uint32_t m = copy.mission;
  cand.verdict = status == source.status ? "still" : "still, " + std::string(to_string(status));
  copy.id = next_id_++;
  // Nothing changed against either neighbour here: it stood still.
  copy.points.changed_against.assign(copy.points.size(), 0);
  copy.update_geometry();
  for (size_t i = 0; i < copy.points.size(); ++i) reported_[m].add(copy.points, i, copy.points.xyz[i]);
  cand.copy = copy.id;
  out_.candidates.push_back(cand);

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
  out_.matches.objects.push_back(c);
  if (groups_) {
    for (size_t g = 0; g < groups_->object_ids.size(); ++g)
      if (groups_->object_ids[g] == source.object_id) {
        out_.groups.object_ids.push_back(copy.id);
        out_.groups.group.push_back(groups_->group[g]);
        if (g < groups_->confidence.size()) out_.groups.confidence.push_back(groups_->confidence[g]);
        break;
      }
  }
  f.chain.push_back(copy.id);
  f.chain_missions.push_back(copy.mission);
  ++out_.copies;
}

void StillFollower::follow(size_t oi) {
  // From out_.matches: an earlier object of the same history may have
  // extended it already (a move in the middle, followed both ways).
  const Object& object = objects_.objects[oi];
  const ObjectChange* c0 = out_.matches.find(object.id);
  if (!c0) return;
  const Direction dir = direction_of(object, *c0, objects_, nm_);
  if (dir.step == 0) return;
  Followed f{oi, *c0, {}, {}, {}};
  const ObjectChange& source = f.source;
  f.chain = source.history.empty() ? std::vector<int>{source.object_id} : source.history;
  for (int id : f.chain)
    if (const Object* m = out_.objects.find(id)) f.chain_missions.push_back(m->mission);
  f.probe0 = sample(object.points);

  // Away from the change, against the object's share where it changed.
  const double there = dir.changed_against >= 0 ? share_near(f.probe0, clouds_[dir.changed_against]) : -1.0;
  walk(f, dir.step, there, source.status, dir.changed_against);

  // Toward it: an added or removed object that stands still in the
  // mission it reportedly changed against, and is gone from its place on
  // the other side, changed against that side instead: its status was
  // wrong. It and its copies take the status the two sides show: still in
  // later missions and gone from an earlier one is added; the reverse,
  // removed. (A move's partner stands in that mission; that contradiction
  // is left alone.)
  const int k = int(object.mission);
  if (cfg_.follow_contradictions && source.status != ChangeStatus::moved && dir.changed_against == k - dir.step &&
      there >= cfg_.min_still_share) {
    const double other_side = share_near(f.probe0, clouds_[k + dir.step]);
    const ChangeStatus shown = -dir.step > 0 ? ChangeStatus::added : ChangeStatus::removed;
    if (there - other_side >= cfg_.min_share_gap && walk(f, -dir.step, other_side, shown, k + dir.step) > 0) {
      out_.matches.find(source.object_id)->status = shown;
      out_.corrected.push_back(source.object_id);
    }
  }

  // Every member of the history lists the whole history, in mission order.
  if (f.chain.size() > (source.history.empty() ? 1u : source.history.size())) {
    std::map<int, uint32_t> mission_of_id;
    for (int id : f.chain) mission_of_id[id] = out_.objects.find(id)->mission;
    std::sort(f.chain.begin(), f.chain.end(), [&](int a, int b) {
      return mission_of_id[a] != mission_of_id[b] ? mission_of_id[a] < mission_of_id[b] : a < b;
    });
    for (int id : f.chain)
      if (ObjectChange* c = out_.matches.find(id)) c->history = f.chain;
  }
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
    const PointSet pts = geometry::points_in_boxes(*mission_of[m], boxes, threads);
    for (size_t i = 0; i < pts.size(); ++i) clouds[m].add(pts, i, pts.xyz[i]);
  }
  for (const Object& o : objects.objects)
    for (size_t i = 0; i < o.points.size(); ++i) reported[o.mission].add(o.points, i, o.points.xyz[i]);

  StillFollower follower(objects, groups, cfg, std::move(clouds), std::move(reported), out);
  for (size_t oi = 0; oi < objects.objects.size(); ++oi) follower.follow(oi);
  return out;
}

}  // namespace lista::history
