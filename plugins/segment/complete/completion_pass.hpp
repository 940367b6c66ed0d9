// One run of complete_objects: the objects being completed, each mission's
// points around them and who owns which point, taken through the rules of
// completion.hpp in order. Internal to segment.complete; completion.cpp
// calls the steps, each rule lives in one method.
#pragma once

#include "local_cloud.hpp"

#include <lista/objects.hpp>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

namespace lista::segment::completion {

// A candidate pair of rules 1-4: objects a and b (indices, consecutive
// missions) and the regions their growth and their floor are taken in.
struct Pair {
  size_t a, b;
  Box own, region, floor_region;  // own: the union of the two boxes, no margin
};

// What each object came with (by mission and first point): its point count
// and floor. An object the pass leaves as it came keeps its floor (rule 7).
using FloorsCameWith = std::map<std::pair<uint32_t, uint64_t>, std::pair<size_t, float>>;

class CompletionPass {
 public:
  // `objects` is completed in place; `mission_of[m]` is the mission of
  // objects.missions[m] (all non-null).
  CompletionPass(ObjectSet& objects, std::vector<const Mission*> mission_of, const CompletionConfig& c);

  // Each mission's points around its objects and around every candidate
  // pair: rule 0 needs each object's floor before the pairs are known.
  void gather_clouds();
  void drop_floor_objects();  // rule 0
  void drop_thin_surfaces();  // rule 0b; renumbers when rule 0 or 0b dropped any
  std::vector<Pair> candidate_pairs_to_try() const;  // rule 1
  // Narrows the clouds to the pairs' regions and the kept objects' own
  // (step 2) and records who owns each point.
  void narrow_clouds(const std::vector<Pair>& pairs);
  // Rules 1-4 (pair_completion.cpp): returns, per object left, whether a
  // completed pair holds it.
  std::vector<char> complete_pairs(const std::vector<Pair>& pairs);
  void join_connected_objects(const std::vector<char>& paired);  // rule 4b
  void self_complete();                                          // rule 5
  void absorb_nested_objects();                                  // rule 6
  void set_floors(const FloorsCameWith& came_with);              // rule 7

  const CompletionStats& stats() const { return st_; }

 private:
  struct Attempt;
  struct PairSides;

  Box own_floor_region(const Object& o) const;
  // The local floor under each object `wanted` (none where it has none),
  // measured side by side.
  std::vector<std::optional<Floor>> own_floors(const std::function<bool(const Object&)>& wanted) const;
  static Box pair_region(const Object& a, const Object& b);
  // (gap in voxels, centroid distance, gap, i, j) across consecutive missions, nearest first.
  std::vector<std::tuple<float, float, float, size_t, size_t>> candidate_pairs() const;
  // Rule 4b's candidates (gap, i, j): free objects of one mission at most
  // pair_gap apart, nearest first (`paired`: aligned with the objects; empty = none).
  std::vector<std::tuple<float, size_t, size_t>> connected_candidates(const std::vector<char>& paired) const;
  std::vector<size_t> neighbours(size_t m) const;
  void add_own_regions(std::vector<std::vector<Box>>& regions, bool with_neighbours) const;
  void add_connected_regions(std::vector<std::vector<Box>>& regions) const;

  // Rules 1-4, one pair (pair_completion.cpp).
  void complete_pair(const Pair& p, std::vector<char>& completed, std::vector<char>& gone);
  Attempt attempt(const PairSides& s, const PointSet& seed_a, const PointSet& seed_b, const Box& own,
                  double strictness, const std::vector<uint32_t>& self, const std::vector<char>& completed,
                  const std::vector<char>& gone) const;
  void commit_pair(const Pair& p, const PairSides& s, const Attempt& t, const std::vector<uint32_t>& join_a,
                   const std::vector<uint32_t>& join_b, std::vector<char>& completed, std::vector<char>& gone);

  ObjectSet& out_;
  std::vector<const Mission*> mission_of_;
  const CompletionConfig& c_;
  const float margin_;
  const size_t nm_;
  std::vector<LocalCloud> clouds_;
  std::vector<Owners> owned_;
  CompletionStats st_;
};

}  // namespace lista::segment::completion
