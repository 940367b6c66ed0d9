#include "shape_sampler.hpp"

#include <lista_objfeat/canonical.hpp>

#include <lista/error.hpp>

#include <algorithm>
#include <cmath>
#include <set>
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

ShapeSampler::ShapeSampler(const objfeat::ViewSet& train, int per_batch, int group,
                           const std::vector<Eigen::Vector3f>& sizes, double share)
    : ShapeSampler(train, per_batch, false) {
  if (group < 1) throw Error("look-alike groups need at least one shape, got " + std::to_string(group));
  if (!(share >= 0.0 && share <= 1.0)) throw Error("look-alike share must lie in 0-1, got " + std::to_string(share));
  grouped_slots_ = int(std::lround(share * per_batch));
  if (sizes.size() != train.views.size())
    throw Error("look-alike sizes: " + std::to_string(sizes.size()) + " rows for " +
                std::to_string(train.views.size()) + " views");
  group_ = group;
  if (group_ == 1) return;
  // Per shape, the median log size over its views (a partial view under-states
  // some extent; the median over viewpoints is the shape's usual look).
  std::vector<int> ids = shapes();
  std::vector<Eigen::Vector3f> typical;
  for (int id : ids) {
    Eigen::Vector3f m;
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<float> v;
      for (int view : views_.at(id)) v.push_back(std::log(std::max(sizes[size_t(view)](axis), 0.01f)));
      std::nth_element(v.begin(), v.begin() + ptrdiff_t(v.size() / 2), v.end());
      m(axis) = v[v.size() / 2];
    }
    typical.push_back(m);
  }
  const size_t take = std::min<size_t>(kLookalikeCandidates, ids.size() - 1);
  for (size_t a = 0; a < ids.size(); ++a) {
    std::vector<std::pair<float, int>> by_distance;
    for (size_t b = 0; b < ids.size(); ++b)
      if (b != a) by_distance.emplace_back((typical[a] - typical[b]).cwiseAbs().sum(), ids[b]);
    std::partial_sort(by_distance.begin(), by_distance.begin() + ptrdiff_t(take), by_distance.end());
    auto& near = lookalikes_[ids[a]];
    for (size_t k = 0; k < take; ++k) near.push_back(by_distance[k].second);
  }
}

std::vector<int> ShapeSampler::draw_groups(std::mt19937_64& rng) {
  auto& pool = by_source_.front();
  std::shuffle(pool.begin(), pool.end(), rng);
  std::vector<int> out;
  std::set<int> taken;
  for (size_t a = 0; a < pool.size() && int(out.size()) < per_batch_; ++a) {
    if (!taken.insert(pool[a]).second) continue;
    out.push_back(pool[a]);
    if (int(out.size()) > grouped_slots_) continue;  // the grouped slots are full: singles
    std::vector<int> near = lookalikes_.at(pool[a]);
    std::shuffle(near.begin(), near.end(), rng);
    int added = 1;
    for (int shape : near) {
      if (added == group_ || int(out.size()) == grouped_slots_) break;
      if (taken.insert(shape).second) { out.push_back(shape); ++added; }
    }
  }
  return out;
}

std::vector<int> ShapeSampler::draw_uniform(std::mt19937_64& rng) {
  if (balance_) throw Error("the uniform draw is not the draw of balanced sources");
  // A full shuffle, then the first per_batch (the draw every shipped model
  // was trained with; changing it changes them).
  auto& pool = by_source_.front();
  std::shuffle(pool.begin(), pool.end(), rng);
  return {pool.begin(), pool.begin() + per_batch_};
}

std::vector<int> ShapeSampler::shapes() const {
  std::vector<int> out;
  for (const auto& [shape, v] : views_) out.push_back(shape);
  return out;
}

std::vector<int> ShapeSampler::draw(std::mt19937_64& rng) {
  if (group_ > 1) return draw_groups(rng);
  if (!balance_) return draw_uniform(rng);
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

std::vector<Eigen::Vector3f> view_sizes(const objfeat::ViewSet& set) {
  objfeat::CanonicalConfig config;
  config.points = 16;  // the globals do not depend on the point count
  std::vector<Eigen::Vector3f> out;
  out.reserve(set.views.size());
  for (const auto& v : set.views) {
    const auto c = objfeat::make_canonical(v.points.xyz, config);
    out.emplace_back(c.globals[6], c.globals[7], c.globals[8]);
  }
  return out;
}

}  // namespace lista::train
