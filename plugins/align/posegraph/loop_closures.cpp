#include "loop_closures.hpp"

#include "ring_key_index.hpp"

#include <lista/error.hpp>
#include <lista/parallel.hpp>
#include <lista_geometry/voxel_key.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_set>

namespace lista::align {

namespace {

// Scans within `distance` of path length either side of `centre`.
std::pair<size_t, size_t> submap_span(const Mission& m, size_t centre, double distance) {
  size_t lo = centre, hi = centre;
  double travelled = 0.0;
  while (lo > 0) {
    travelled += (m.scans[lo].pose.translation() - m.scans[lo - 1].pose.translation()).norm();
    if (travelled > distance) break;
    --lo;
  }
  travelled = 0.0;
  while (hi + 1 < m.scans.size()) {
    travelled += (m.scans[hi + 1].pose.translation() - m.scans[hi].pose.translation()).norm();
    if (travelled > distance) break;
    ++hi;
  }
  return {lo, hi};
}

}  // namespace

std::vector<Keyframe> make_keyframes(const MissionSet& set, const KeyframeOptions& o, int threads) {
  std::vector<Keyframe> keyframes;
  for (size_t mi = 0; mi < set.missions.size(); ++mi) {
    const Mission& m = set.missions[mi];
    Eigen::Isometry3d last;
    double travelled = 0.0;
    for (size_t s = 0; s < m.scans.size(); ++s) {
      const Eigen::Isometry3d& pose = m.scans[s].pose;
      if (s > 0) travelled += (pose.translation() - m.scans[s - 1].pose.translation()).norm();
      const bool take = s == 0 || (pose.translation() - last.translation()).norm() >= o.keyframe_distance ||
                        rotation_angle(last.linear().transpose() * pose.linear()) >= o.keyframe_angle;
      if (!take) continue;
      Keyframe k;
      k.mission = mi;
      k.scan = s;
      k.travelled = travelled;
      k.frame = levelled_frame(pose);
      keyframes.push_back(std::move(k));
      last = pose;
    }
  }
  const double max_r = o.scan_context.max_radius;
  std::vector<char> whole(keyframes.size(), 0);  // the span already holds the keyframe's whole mission
  auto build = [&](double distance) {
    parallel_for(keyframes.size(), threads, [&](size_t i) {
      Keyframe& k = keyframes[i];
      const Mission& m = set.missions[k.mission];
      const auto [lo, hi] = submap_span(m, k.scan, distance);
      whole[i] = lo == 0 && hi + 1 == m.scans.size();
      Cloud local;
      const Eigen::Isometry3d frame_inv = k.frame.inverse();
      for (size_t s = lo; s <= hi; ++s) {
        if (!m.scans[s].points) continue;
        const Eigen::Isometry3f t = (frame_inv * m.scans[s].pose).cast<float>();
        for (const auto& p : m.scans[s].points->xyz) {
          const Eigen::Vector3f q = t * p;
          if (q.head<2>().squaredNorm() < max_r * max_r) local.push_back(q);
        }
      }
      k.descriptor = make_scan_context(local, o.scan_context);
      k.submap = voxel_downsample(local, o.voxel);
      k.submap_distance = distance;
    });
  };
  // One span for every keyframe: a grown submap beside an ungrown one
  // overlaps it too little both ways to pass verification.
  for (double distance = o.submap_distance;; distance += o.submap_distance) {
    build(distance);
    if (keyframes.empty() || o.submap_min_points == 0 || o.submap_distance <= 0.0 ||
        distance + o.submap_distance > o.submap_max_distance + 1e-9 ||
        std::all_of(whole.begin(), whole.end(), [](char w) { return w != 0; }))
      break;
    std::vector<size_t> sizes;
    for (const Keyframe& k : keyframes) sizes.push_back(k.submap.size());
    if (geometry::median(sizes) >= o.submap_min_points) break;
  }
  return keyframes;
}

std::vector<Candidate> find_candidates(const std::vector<Keyframe>& keyframes, size_t mission_count,
                                       const CandidateOptions& o, int threads) {
  std::vector<std::vector<size_t>> members(mission_count);
  for (size_t i = 0; i < keyframes.size(); ++i) members[keyframes[i].mission].push_back(i);
  std::vector<std::unique_ptr<RingKeyIndex>> indices;
  for (const auto& list : members) {
    std::vector<Eigen::VectorXf> keys;
    for (size_t i : list) keys.push_back(keyframes[i].descriptor.ring_key);
    indices.push_back(std::make_unique<RingKeyIndex>(keys));
  }
  // One slot per (query keyframe, earlier mission): filled in parallel, read in order.
  std::vector<std::vector<Candidate>> found(keyframes.size());
  parallel_for(keyframes.size(), threads, [&](size_t q) {
    const Keyframe& query = keyframes[q];
    for (size_t a = 0; a <= query.mission; ++a) {
      if (a == query.mission && (!o.intra || query.travelled < o.intra_min_travel)) break;
      Candidate best;
      bool any = false;
      // Within one mission the nearest ring keys are mostly the keyframes just
      // before: look further down the list.
      const size_t k = a == query.mission ? 4 * o.neighbours : o.neighbours;
      for (size_t j : indices[a]->nearest(query.descriptor.ring_key, k)) {
        const size_t r = members[a][j];
        if (a == query.mission && query.travelled - keyframes[r].travelled < o.intra_min_travel) continue;
        const ScanContextMatch match = compare(keyframes[r].descriptor, query.descriptor);
        if (match.distance <= o.max_descriptor_distance && (!any || match.distance < best.distance)) {
          best = {r, q, match.distance, match.yaw};
          any = true;
        }
      }
      if (any) found[q].push_back(best);
    }
  });
  std::map<std::pair<size_t, size_t>, std::vector<Candidate>> by_pair;
  for (const auto& list : found)
    for (const auto& c : list) by_pair[{keyframes[c.reference].mission, keyframes[c.query].mission}].push_back(c);
  std::vector<Candidate> out;
  for (auto& [pair, list] : by_pair) {
    std::stable_sort(list.begin(), list.end(), [](const Candidate& a, const Candidate& b) { return a.distance < b.distance; });
    if (static_cast<int>(list.size()) > o.per_pair) list.resize(o.per_pair);
    out.insert(out.end(), list.begin(), list.end());
  }
  return out;
}

std::vector<Closure> verify_candidates(const std::vector<Keyframe>& keyframes,
                                       const std::vector<Candidate>& candidates,
                                       const std::vector<Eigen::Isometry3d>& guesses,
                                       const VerifyOptions& o, int threads) {
  if (!guesses.empty() && guesses.size() != candidates.size())
    throw Error("loop closure verification: one guess per candidate expected");
  // Each keyframe's submap prepared once, however many candidates it is in.
  std::vector<size_t> used;
  for (const auto& c : candidates) used.insert(used.end(), {c.reference, c.query});
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<PreparedCloud> prepared(used.size());
  parallel_for(used.size(), threads,
               [&](size_t i) { prepared[i] = PreparedCloud(keyframes[used[i]].submap, o.registration); });
  auto prepared_of = [&](size_t keyframe) -> const PreparedCloud& {
    return prepared[size_t(std::lower_bound(used.begin(), used.end(), keyframe) - used.begin())];
  };
  std::vector<std::optional<Closure>> results(candidates.size());
  parallel_for(candidates.size(), threads, [&](size_t i) {
    const Candidate& c = candidates[i];
    Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
    if (guesses.empty()) guess.linear() = Eigen::AngleAxisd(c.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    else guess = guesses[i];
    const RegistrationResult r =
        register_prepared(prepared_of(c.query), prepared_of(c.reference), guess, o.registration);
    // Overlap both ways: a floor alone matches a floor, but the walls and
    // furniture of the other submap then find no partner.
    const double overlap = std::min(r.overlap, r.reverse_overlap);
    if (!r.converged || overlap < o.min_overlap || r.inlier_rmse > o.max_rmse) return;
    results[i] = Closure{c.reference, c.query, r.transform, overlap, r.inlier_rmse, c.distance};
  });
  std::vector<Closure> out;
  for (auto& r : results)
    if (r) out.push_back(*r);
  return out;
}

namespace {

// How well one mission's map lies on another's under a candidate
// map-to-map transform. Walls fit a symmetric room turned by half a turn as
// well as unturned; the furniture standing in it does not, and this counts
// all of it at once. The reference mission's occupied voxels are gathered
// once and serve every hypothesis of the pair.
class MapAgreement {
 public:
  MapAgreement(const std::vector<Keyframe>& keyframes, size_t reference, double voxel)
      : keyframes_(keyframes), voxel_(voxel) {
    for (const Keyframe& kf : keyframes)
      if (kf.mission == reference)
        for (const auto& p : kf.submap) occupied_.insert(key(kf.frame * p.cast<double>()));
  }
  // Share of mission `query`'s keyframe points that land, moved by
  // `query_to_reference`, in a voxel the reference mission occupies.
  double operator()(size_t query, const Eigen::Isometry3d& query_to_reference) const {
    size_t hits = 0, total = 0;
    for (const Keyframe& kf : keyframes_)
      if (kf.mission == query) {
        const Eigen::Isometry3d to_reference = query_to_reference * kf.frame;
        for (const auto& p : kf.submap) {
          hits += occupied_.count(key(to_reference * p.cast<double>()));
          ++total;
        }
      }
    return total ? double(hits) / double(total) : 0.0;
  }

 private:
  uint64_t key(const Eigen::Vector3d& p) const { return geometry::voxel_key_of(p, voxel_); }
  const std::vector<Keyframe>& keyframes_;
  double voxel_;
  std::unordered_set<uint64_t> occupied_;
};

}  // namespace

Eigen::Isometry3d implied_map_transform(const std::vector<Keyframe>& keyframes, const Closure& c) {
  return keyframes[c.reference].frame * c.reference_T_query * keyframes[c.query].frame.inverse();
}

// How many closures of one hypothesis are tried as its placement.
constexpr size_t kScoredPerHypothesis = 8;

std::vector<Closure> consistent_closures(const std::vector<Keyframe>& keyframes, const std::vector<Closure>& closures,
                                         const ConsistencyOptions& o, std::vector<AmbiguousPlacement>* ambiguous,
                                         int threads) {
  std::map<std::pair<size_t, size_t>, std::vector<size_t>> by_pair;
  for (size_t i = 0; i < closures.size(); ++i)
    by_pair[{keyframes[closures[i].reference].mission, keyframes[closures[i].query].mission}].push_back(i);
  std::vector<bool> keep(closures.size(), false);
  for (const auto& [pair, list] : by_pair) {
    std::vector<Eigen::Isometry3d> maps;
    for (size_t i : list) maps.push_back(implied_map_transform(keyframes, closures[i]));
    // i and j agree if both put j's keyframe in the same place and turn alike;
    // compared at the keyframe so that a small drift far away does not count.
    auto agree = [&](size_t i, size_t j) {
      const Eigen::Vector3d p = keyframes[closures[list[j]].query].frame.translation();
      return (maps[i] * p - maps[j] * p).norm() <= o.distance &&
             rotation_angle(maps[i].linear().transpose() * maps[j].linear()) <= o.angle;
    };
    size_t best = 0, best_support = 0;
    std::vector<size_t> support(list.size(), 0);
    for (size_t i = 0; i < list.size(); ++i) {
      for (size_t j = 0; j < list.size(); ++j) support[i] += agree(i, j) ? 1 : 0;
      if (support[i] > best_support ||
          (support[i] == best_support && closures[list[i]].rmse < closures[list[best]].rmse)) {
        best = i;
        best_support = support[i];
      }
    }
    // A rival hypothesis (disagreeing with the best) wins if the whole maps
    // agree clearly better under it: in a symmetric room the closures split
    // between the true and the half-turned fit, and the count alone may pick
    // the wrong one.
    if (o.rival_margin > 0 && pair.first != pair.second) {
      std::vector<size_t> order(list.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return support[a] > support[b]; });
      std::vector<size_t> rivals;  // the best-backed closure of each distinct rival hypothesis
      for (size_t i : order) {
        if (agree(best, i) || support[i] < size_t(o.rival_min_support)) continue;
        if (std::none_of(rivals.begin(), rivals.end(), [&](size_t r) { return agree(r, i); })) rivals.push_back(i);
      }
      if (!rivals.empty()) {
        const MapAgreement on_reference(keyframes, pair.first, o.agreement_voxel);
        // The voted hypothesis is scored by the best placement among its
        // closures (up to kScoredPerHypothesis of them, spread over the
        // list), a rival by its own best-backed closure: each closure's
        // placement fits the maps near its own keyframes, and where the
        // missions drift, the voted fit's best-backed closure can place the
        // far end of the map worse than a half-turned rival does. Votes are
        // overruled only by a rival that beats the best the voted fit shows.
        std::vector<size_t> scored_members;
        for (size_t j = 0; j < list.size(); ++j)
          if (j != best && agree(best, j)) scored_members.push_back(j);
        const size_t step =
            std::max<size_t>(1, (scored_members.size() + kScoredPerHypothesis - 1) / kScoredPerHypothesis);
        // Each placement's agreement measured once, all of them side by side.
        std::vector<size_t> measured{best};
        for (size_t k = 0; k < scored_members.size(); k += step) measured.push_back(scored_members[k]);
        measured.insert(measured.end(), rivals.begin(), rivals.end());
        std::vector<double> agreements(measured.size());
        parallel_for(measured.size(), threads,
                     [&](size_t k) { agreements[k] = on_reference(pair.second, maps[measured[k]]); });
        auto agreement = [&](size_t i) {
          return agreements[size_t(std::find(measured.begin(), measured.end(), i) - measured.begin())];
        };
        double best_agreement = agreement(best);
        for (size_t k = 0; k < scored_members.size(); k += step)
          best_agreement = std::max(best_agreement, agreement(scored_members[k]));
        std::vector<std::pair<size_t, double>> scored{{best, best_agreement}};
        for (size_t r : rivals) {
          const double a = agreement(r);
          scored.emplace_back(r, a);
          if (a > best_agreement + o.rival_margin) {
            best = r;
            best_agreement = a;
          }
        }
        // The closest runner-up (a hypothesis the chosen one disagrees with):
        // within the margin, the maps cannot tell them apart.
        const std::pair<size_t, double>* close = nullptr;
        for (const auto& s : scored)
          if (!agree(best, s.first) && s.second >= best_agreement - o.rival_margin &&
              (!close || s.second > close->second))
            close = &s;
        if (close && ambiguous) {
          AmbiguousPlacement a;
          a.reference = pair.first;
          a.query = pair.second;
          a.turn_deg = rotation_angle(maps[best].linear().transpose() * maps[close->first].linear()) * 180.0 / M_PI;
          Eigen::Vector3d centre = Eigen::Vector3d::Zero();
          size_t count = 0;
          for (const Keyframe& kf : keyframes)
            if (kf.mission == pair.second) centre += kf.frame.translation(), ++count;
          if (count) centre /= double(count);
          a.shift_m = (maps[best] * centre - maps[close->first] * centre).norm();
          a.chosen_agreement = best_agreement;
          a.rival_agreement = close->second;
          ambiguous->push_back(a);
        }
      }
    }
    for (size_t j = 0; j < list.size(); ++j)
      if (agree(best, j)) keep[list[j]] = true;
  }
  std::vector<Closure> out;
  for (size_t i = 0; i < closures.size(); ++i)
    if (keep[i]) out.push_back(closures[i]);
  return out;
}

}  // namespace lista::align

