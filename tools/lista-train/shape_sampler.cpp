#include "shape_sampler.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <string>

namespace lista::train {

ShapeSampler::ShapeSampler(const objfeat::ViewSet& train, int per_batch, bool balance_sources)
    : per_batch_(per_batch), balance_(balance_sources) {
  std::map<int, int> source_of;
  for (size_t i = 0; i < train.views.size(); ++i) {
    views_[train.views[i].label].push_back(int(i));
    source_of[train.views[i].label] = train.views[i].source;
  }
  for (auto it = views_.begin(); it != views_.end();) it = it->second.size() < 2 ? views_.erase(it) : std::next(it);
  if (int(views_.size()) < per_batch)
    throw Error("training needs at least " + std::to_string(per_batch) + " shapes with two or more views, got " +
                std::to_string(views_.size()));
  std::map<int, std::vector<int>> grouped;
  for (const auto& [shape, v] : views_) grouped[balance_ ? source_of[shape] : 0].push_back(shape);
  for (auto& [source, shapes] : grouped) by_source_.push_back(std::move(shapes));
}

std::vector<int> ShapeSampler::shapes() const {
  std::vector<int> out;
  for (const auto& [shape, v] : views_) out.push_back(shape);
  return out;
}

std::vector<int> ShapeSampler::draw(std::mt19937_64& rng) {
  if (!balance_) {
    // Uniform over shapes: a full shuffle, then the first per_batch (the
    // draw every shipped model was trained with; changing it changes them).
    auto& pool = by_source_.front();
    std::shuffle(pool.begin(), pool.end(), rng);
    return {pool.begin(), pool.begin() + per_batch_};
  }
  // Slots per source: an even share, the remainder to random sources.
  const size_t n = by_source_.size();
  std::vector<int> quota(n, per_batch_ / int(n));
  std::vector<size_t> order(n);
  for (size_t s = 0; s < n; ++s) order[s] = s;
  std::shuffle(order.begin(), order.end(), rng);
  for (int r = 0; r < per_batch_ % int(n); ++r) ++quota[order[size_t(r)]];
  // A source short of shapes hands its missing slots to the next ones.
  int spill = 0;
  for (size_t s : order) {
    quota[s] += spill;
    spill = std::max(0, quota[s] - int(by_source_[s].size()));
    quota[s] -= spill;
  }
  for (size_t s : order) {  // second round: spill from the last sources goes to the first
    const int room = int(by_source_[s].size()) - quota[s];
    const int take = std::min(room, spill);
    quota[s] += take;
    spill -= take;
  }
  std::vector<int> out;
  for (size_t s = 0; s < n; ++s) {
    // Partial Fisher-Yates: quota[s] distinct shapes of source s.
    auto& pool = by_source_[s];
    for (int k = 0; k < quota[s]; ++k) {
      std::uniform_int_distribution<size_t> pick(size_t(k), pool.size() - 1);
      std::swap(pool[size_t(k)], pool[pick(rng)]);
      out.push_back(pool[size_t(k)]);
    }
  }
  return out;
}

}  // namespace lista::train
