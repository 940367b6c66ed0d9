// Which training shapes a batch holds. Uniform over shapes by default; with
// balanced sources every source (procedural, furniture, ...) gets an equal
// share of each batch, so adding shapes of one source does not crowd out
// another's (ViewSet::sources).
#pragma once

#include <lista_objfeat/views.hpp>

#include <map>
#include <random>
#include <vector>

namespace lista::train {

class ShapeSampler {
 public:
  // Shapes (labels) with at least two views; throws lista::Error when fewer
  // than `per_batch` of them exist.
  ShapeSampler(const objfeat::ViewSet& train, int per_batch, bool balance_sources);
  // `per_batch` distinct shapes. Balanced: the sources share the slots
  // evenly (the remainder to randomly chosen sources); a source with too
  // few shapes leaves its slots to the others.
  std::vector<int> draw(std::mt19937_64& rng);
  // Views of one shape (indices into the training set).
  const std::vector<int>& views_of(int shape) const { return views_.at(shape); }
  // Ids of the shapes that batches may hold (sorted; label order).
  std::vector<int> shapes() const;

 private:
  int per_batch_;
  bool balance_;
  std::map<int, std::vector<int>> views_;
  std::vector<std::vector<int>> by_source_;  // shapes of each source that has any
};

}  // namespace lista::train
