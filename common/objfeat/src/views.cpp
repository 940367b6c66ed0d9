#include <lista_objfeat/synthetic.hpp>
#include <lista_objfeat/views.hpp>

#include <algorithm>
#include <random>
#include <set>

namespace lista::objfeat {

ViewSet synthetic_views(int shapes, int per_instance, uint64_t seed) {
  ViewSet out;
  out.sources = {"synthetic"};
  std::mt19937_64 rng(seed);
  for (int s = 0; s < shapes; ++s) {
    Shape shape = random_shape(rng);
    for (int v = 0; v < per_instance; ++v) {
      View view;
      view.label = view.variant = view.instance = s;
      view.points.xyz = render_view(shape, 0.f, {0.f, 0.f}, rng);
      view.points.scan.assign(view.points.size(), 0);
      view.points.index.resize(view.points.size());
      for (size_t i = 0; i < view.points.size(); ++i) view.points.index[i] = uint32_t(i);
      out.views.push_back(std::move(view));
    }
  }
  return out;
}

void split_by_shape(const ViewSet& all, double holdout, uint64_t seed, ViewSet& train, ViewSet& test) {
  train.sources = test.sources = all.sources;
  if (!all.views.empty() && all.views.front().split >= 0) {
    for (const auto& v : all.views) (v.split == 1 ? test : train).views.push_back(v);
    return;
  }
  std::set<int> label_set;
  for (const auto& v : all.views) label_set.insert(v.label);
  std::vector<int> labels(label_set.begin(), label_set.end());
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
  std::shuffle(labels.begin(), labels.end(), rng);
  size_t n_test = std::min(labels.size(), size_t(double(labels.size()) * holdout + 0.5));
  std::set<int> held(labels.begin(), labels.begin() + long(n_test));
  for (const auto& v : all.views) (held.count(v.label) ? test : train).views.push_back(v);
}

}  // namespace lista::objfeat
