// Which training shapes a batch holds. Uniform over shapes by default; with
// balanced sources every source (procedural, furniture, ...) gets an equal
// share of each batch, so adding shapes of one source does not crowd out
// another's (ViewSet::sources). With look-alike groups a batch is made of
// groups: a random shape and shapes of nearly its size, so batch-hard mining
// meets the near look-alikes (same class, a few cm apart) that uniform
// batches of a thousand shapes almost never hold together.
#pragma once

#include <lista_objfeat/views.hpp>

#include <Eigen/Core>

#include <map>
#include <random>
#include <vector>

namespace lista::train {

class ShapeSampler {
 public:
  // Shapes (labels) with at least two views; throws lista::Error when fewer
  // than `per_batch` of them exist.
  ShapeSampler(const objfeat::ViewSet& train, int per_batch, bool balance_sources);
  // Look-alike groups of `group` shapes (1: off, the uniform draw): each
  // group is a random anchor shape plus group - 1 shapes drawn from the
  // anchor's kLookalikeCandidates nearest by `sizes` (one row per view of
  // `train`, e.g. view_sizes(); compared in log space, per shape the
  // median over its views). Throws lista::Error for group < 1, when
  // sizes has the wrong row count, or for a share outside 0-1. Sources are
  // not balanced in this mode.
  // `share` of the batch's slots (rounded, 0-1) go to groups, the rest to
  // single shapes drawn uniformly.
  ShapeSampler(const objfeat::ViewSet& train, int per_batch, int group, const std::vector<Eigen::Vector3f>& sizes,
               double share = 1.0);
  static constexpr int kLookalikeCandidates = 8;
  // `per_batch` distinct shapes. Balanced: the sources share the slots
  // evenly (the remainder to randomly chosen sources); a source with too
  // few shapes leaves its slots to the others.
  std::vector<int> draw(std::mt19937_64& rng);
  // The uniform draw in look-alike mode (what draw gives with groups off and
  // sources unbalanced); throws lista::Error when sources are balanced.
  std::vector<int> draw_uniform(std::mt19937_64& rng);
  // Views of one shape (indices into the training set).
  const std::vector<int>& views_of(int shape) const { return views_.at(shape); }
  // Ids of the shapes that batches may hold (sorted; label order).
  std::vector<int> shapes() const;
  // The look-alike candidates of a shape, nearest first (empty when off).
  const std::vector<int>& lookalikes_of(int shape) const { return lookalikes_.at(shape); }

 private:
  int per_batch_;
  bool balance_;
  std::map<int, std::vector<int>> views_;
  std::vector<std::vector<int>> by_source_;  // shapes of each source that has any
  int group_ = 1;
  int grouped_slots_ = 0;
  std::map<int, std::vector<int>> lookalikes_;

  std::vector<int> draw_groups(std::mt19937_64& rng);
};

// Each view's size: the 2nd-98th percentile spreads along the canonical
// axes (canonical.hpp globals 6-8), robust to stray points.
std::vector<Eigen::Vector3f> view_sizes(const objfeat::ViewSet& set);

}  // namespace lista::train
