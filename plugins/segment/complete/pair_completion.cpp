// Rules 1-4 of completion.hpp: grow both objects of each candidate pair;
// keep the growth if the shapes agree. With join_fragments, a growth that
// reaches points of other free objects of its own mission (a short move
// with a turn leaves slivers at both ends of a desk) is tried again with
// them in the seed and their boxes in the region; if those shapes agree,
// they are joined into the pair's object.
#include "completion_pass.hpp"

#include "growth_checks.hpp"
#include "object_merges.hpp"

#include <lista_objreg/icp_refine.hpp>
#include <lista_objreg/surface_share.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace lista::segment::completion {
namespace {

// Rounds of joining: a joined fragment's growth may reach one more.
constexpr int kJoinRounds = 3;
// Joined shapes must agree within this share of the pair check's allowance:
// joining claims more than pairing, and the pair check's allowance is wide
// enough for a desk in one mission to pass for a barrel and a cart touching
// in the other (measured on tiny seed 3).
constexpr double kJoinStrictness = 0.5;

// "1, 4, 7": the ids of the objects `a` and `b` name.
std::string id_list(const ObjectSet& set, const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  std::string ids;
  for (const auto* list : {&a, &b})
    for (uint32_t k : *list) ids += (ids.empty() ? "" : ", ") + std::to_string(set.objects[k].id);
  return ids;
}

// The two grown objects of a pair registered onto each other
// (lista::objreg's ICP from yaw turns about the centroids).
struct RegisteredFit {
  bool checked = false;            // registered at all
  double shift = 0.0, turn = 0.0;  // m, degrees: how far the pose moves the first
  double moved = 0.0, unmoved = 0.0;  // fit at that pose, and where they stand
  // A rigid move registers one grown object onto the other by the move; two
  // growths into the same static thing (a desk between a box taken away and
  // a barrel put down) fit best where they stand.
  bool still() const { return checked && ((shift < 0.05 && turn < 5.0) || unmoved > moved); }
  std::string note() const {
    return "registered " + format_number(shift) + " m, " + format_number(turn) + " degrees apart, fit " +
           format_number(moved) + ", unmoved " + format_number(unmoved);
  }
};

RegisteredFit registered_fit(const std::vector<Eigen::Vector3f>& a, const std::vector<Eigen::Vector3f>& b) {
  const objreg::IcpConfig rc = objreg::shape_check_config(0.04, 0.05);  // match.weighted's defaults
  const objreg::IcpResult r = objreg::icp_refine(a, b, rc);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : a) c += p.cast<double>();
  c /= double(std::max<size_t>(a.size(), 1));
  objreg::SurfaceShareConfig shares;  // on the surfaces, as match.weighted judges its pairs
  shares.voxel = rc.voxel;
  shares.inlier = rc.inlier_distance;
  shares.max_points = rc.max_score_points;
  auto fit_at = [&](const Eigen::Isometry3d& pose) {
    const objreg::SurfaceShares on = objreg::surface_shares(a, b, pose, shares);
    return objreg::shape_fit(on.source, on.target);
  };
  RegisteredFit f;
  f.checked = true;
  f.shift = (r.transform * c - c).norm();
  f.turn = Eigen::AngleAxisd(r.transform.rotation()).angle() * 180.0 / M_PI;
  f.moved = fit_at(r.transform);
  f.unmoved = fit_at(Eigen::Isometry3d::Identity());
  return f;
}

}  // namespace

// One growth of both sides and what it gave.
struct CompletionPass::Attempt {
  Growth ga, gb;
  Eigen::Vector3f sa, sb;
  bool contained = false, same = false;
  RegisteredFit fit;  // with still_check, once the shapes agree
  std::string kept_to;
  std::vector<uint32_t> touched_a, touched_b;  // free objects the growths reached
};

// A pair's two objects with their clouds and floors.
struct CompletionPass::PairSides {
  Object &a, &b;
  const LocalCloud &ca, &cb;
  float floor_a, floor_b, min_a, min_b;
};

std::vector<char> CompletionPass::complete_pairs(const std::vector<Pair>& pairs) {
  std::vector<char> completed(out_.objects.size(), 0), gone(out_.objects.size(), 0);
  for (const auto& p : pairs) {
    if (completed[p.a] || completed[p.b] || gone[p.a] || gone[p.b]) continue;
    complete_pair(p, completed, gone);
  }
  std::vector<char> paired;  // aligned with out_.objects from here
  for (size_t k = 0; k < out_.objects.size(); ++k)
    if (!gone[k]) paired.push_back(completed[k]);
  // owned_'s object indices are stale from here; later rules only test membership.
  if (st_.joined) drop_objects(out_, gone);
  return paired;
}

// `own`: the union of the seeds' boxes, no margin. `self`: the objects the
// seeds are made of, which their growths may reach without joining them.
CompletionPass::Attempt CompletionPass::attempt(const PairSides& s, const PointSet& seed_a, const PointSet& seed_b,
                                                const Box& own, double strictness, const std::vector<uint32_t>& self,
                                                const std::vector<char>& completed,
                                                const std::vector<char>& gone) const {
  auto free_touched = [&](const std::vector<uint32_t>& touched) {
    std::vector<uint32_t> f;
    for (uint32_t k : touched)
      if (std::find(self.begin(), self.end(), k) == self.end() && !completed[k] && !gone[k] &&
          !out_.objects[k].points.empty())
        f.push_back(k);
    return f;
  };
  Attempt t;
  auto grow_both = [&](const Box& region) {
    Box ra = region, rb = region;
    ra.lo.z() = std::min(ra.lo.z(), s.min_a);
    rb.lo.z() = std::min(rb.lo.z(), s.min_b);
    t.ga = grow(seed_a, s.ca, ra, s.min_a, owned_[s.a.mission]);
    t.gb = grow(seed_b, s.cb, rb, s.min_b, owned_[s.b.mission]);
    t.sa = shape_of(seed_a, t.ga.added, s.ca.points, s.floor_a, s.min_a);
    t.sb = shape_of(seed_b, t.gb.added, s.cb.points, s.floor_b, s.min_b);
  };
  grow_both(own.grown(margin_, 0.f, margin_));
  t.touched_a = free_touched(t.ga.touched);
  t.touched_b = free_touched(t.gb.touched);
  t.contained = t.ga.contained(c_.max_leak) && t.gb.contained(c_.max_leak);
  if (!t.contained && c_.leak_growth == LeakGrowth::own_box) {
    // As in rule 5: what leaks is the thing they touch; the pair's own box
    // (the two clusters' union, no margin) holds the object. The shapes
    // must still agree.
    t.kept_to = " inside the pair's own box (a growth leaked: " + leak_note(t.ga) + " / " + leak_note(t.gb) + ")";
    grow_both(own);
    t.contained = true;
  }
  t.same = t.contained && same_shape(t.sa, t.sb, c_, strictness);
  if (t.same && c_.still_check) {
    std::vector<Eigen::Vector3f> ga = seed_a.xyz, gb = seed_b.xyz;
    for (uint32_t i : t.ga.added) ga.push_back(s.ca.points.xyz[i]);
    for (uint32_t i : t.gb.added) gb.push_back(s.cb.points.xyz[i]);
    t.fit = registered_fit(ga, gb);
    if (t.fit.still()) t.same = false;
  }
  return t;
}

void CompletionPass::complete_pair(const Pair& p, std::vector<char>& completed, std::vector<char>& gone) {
  ++st_.pairs;
  Object &a = out_.objects[p.a], &b = out_.objects[p.b];
  const LocalCloud &ca = clouds_[a.mission], &cb = clouds_[b.mission];
  Floor fa, fb;
  const std::string which = "objects " + std::to_string(a.id) + " + " + std::to_string(b.id) + ": ";
  // Why an attempt was not kept, for -v.
  auto refusal = [](const Attempt& t, const std::string& leaked, const std::string& shapes) {
    if (!t.contained) return leaked;
    if (t.fit.still()) return "the grown objects fit best where they stand (" + t.fit.note() + ")";
    return shapes + " differ" + t.kept_to + " (" + shape_note(t.sa) + " / " + shape_note(t.sb) + ")";
  };
  if (!local_floor(ca, p.floor_region, c_.floor_percentile, c_.floor_clearance, fa) ||
      !local_floor(cb, p.floor_region, c_.floor_percentile, c_.floor_clearance, fb)) {
    ++st_.rejected;
    st_.pair_notes.push_back(which + "not completed, no floor found around them");
    return;
  }
  const PairSides s{a, b, ca, cb, fa.z, fb.z, fa.clear_z, fb.clear_z};
  const std::vector<uint32_t> pair_self{uint32_t(p.a), uint32_t(p.b)};
  Attempt t = attempt(s, a.points, b.points, p.own, 1.0, pair_self, completed, gone);
  std::vector<uint32_t> join_a, join_b;
  if (c_.join_fragments && (!t.touched_a.empty() || !t.touched_b.empty())) {
    // Both sides' fragments, else one side's only (the other side's growth
    // may reach a different object touching it, as a desk touches a
    // cabinet added beside it).
    auto try_join = [&](bool side_a, bool side_b, std::vector<uint32_t>& ja, std::vector<uint32_t>& jb) {
      std::vector<uint32_t> self = pair_self;
      PointSet seed_a = a.points, seed_b = b.points;
      Box own = p.own;
      Attempt joined = t;
      auto pending = [&] { return (side_a && !joined.touched_a.empty()) || (side_b && !joined.touched_b.empty()); };
      for (int round = 0; round < kJoinRounds && pending(); ++round) {
        for (auto [use, touched, seed, into] : {std::tuple{side_a, &joined.touched_a, &seed_a, &ja},
                                                std::tuple{side_b, &joined.touched_b, &seed_b, &jb}})
          if (use)
            for (uint32_t k : *touched) {
              const Object& f = out_.objects[k];
              seed->append(f.points);
              own.extend(Box{f.bbox_min, f.bbox_max});
              into->push_back(k);
              self.push_back(k);
            }
        joined = attempt(s, seed_a, seed_b, own, kJoinStrictness, self, completed, gone);
      }
      return joined;
    };
    const bool both = !t.touched_a.empty() && !t.touched_b.empty();
    std::vector<std::pair<bool, bool>> tries;
    if (both) tries = {{true, true}, {true, false}, {false, true}};
    else tries = {{!t.touched_a.empty(), !t.touched_b.empty()}};
    for (auto [side_a, side_b] : tries) {
      std::vector<uint32_t> ja, jb;
      Attempt joined = try_join(side_a, side_b, ja, jb);
      if (joined.same) {
        t = std::move(joined);
        join_a = std::move(ja);
        join_b = std::move(jb);
        break;
      }
      st_.pair_notes.push_back(which + "not joined with " + id_list(out_, ja, jb) + ", " +
                               refusal(joined, "a growth leaks out of the region", "joined shapes"));
    }
  }
  if (!t.same) {
    ++st_.rejected;
    st_.pair_notes.push_back(which + "not completed, " +
                             refusal(t,
                                     "a growth leaks out of the pair's region (" + leak_note(t.ga) + " / " +
                                         leak_note(t.gb) + ", max_leak " + format_number(c_.max_leak) + ")",
                                     "grown shapes"));
    return;
  }
  commit_pair(p, s, t, join_a, join_b, completed, gone);
}

// The pair's growth, and the fragments joined, become the pair's objects.
void CompletionPass::commit_pair(const Pair& p, const PairSides& s, const Attempt& t,
                                 const std::vector<uint32_t>& join_a, const std::vector<uint32_t>& join_b,
                                 std::vector<char>& completed, std::vector<char>& gone) {
  ++st_.completed;
  completed[p.a] = completed[p.b] = 1;
  std::string joined_note;
  for (auto [join, into] : {std::pair{&join_a, &s.a}, std::pair{&join_b, &s.b}})
    for (uint32_t k : *join) {
      Object& f = out_.objects[k];
      joined_note += (joined_note.empty() ? " (joined: " : ", ") + std::to_string(f.id) + " to " + std::to_string(into->id);
      into->points.append(f.points);
      const uint32_t to = uint32_t(into == &s.a ? p.a : p.b);
      for (size_t i = 0; i < f.points.size(); ++i) owned_[f.mission][point_key(f.points.scan[i], f.points.index[i])] = to;
      f.points = PointSet();
      gone[k] = 1;
      ++st_.joined;
    }
  if (!joined_note.empty()) joined_note += ")";
  st_.pair_notes.push_back("objects " + std::to_string(s.a.id) + " + " + std::to_string(s.b.id) + ": completed" +
                           joined_note + t.kept_to + ", " + std::to_string(t.ga.added.size()) + " + " +
                           std::to_string(t.gb.added.size()) + " points added (" + shape_note(t.sa) + " / " +
                           shape_note(t.sb) + ")");
  for (auto [o, add, cloud, index] :
       {std::tuple{&s.a, &t.ga.added, &s.ca, uint32_t(p.a)}, std::tuple{&s.b, &t.gb.added, &s.cb, uint32_t(p.b)}}) {
    add_points(*o, cloud->points, *add);
    for (uint32_t i : *add) owned_[o->mission][point_key(cloud->points.scan[i], cloud->points.index[i])] = index;
    st_.points_added += add->size();
    o->update_geometry();
  }
}

}  // namespace lista::segment::completion
