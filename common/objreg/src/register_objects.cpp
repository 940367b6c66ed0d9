#include <lista_objreg/register_objects.hpp>

#include <lista/error.hpp>
#include <lista/parallel.hpp>

#include <algorithm>
#include <map>
#include <utility>

namespace lista::objreg {

Matches register_matches(const ObjectSet& objects, const Matches& matches, const PairRegistration& reg,
                         Context& ctx) {
  Matches out = matches;
  // Unordered pairs, lower id first: registered once, deterministic order.
  std::vector<std::pair<int, int>> pairs;
  for (const ObjectChange& c : matches.objects) {
    if (c.status != ChangeStatus::moved || c.match < 0) continue;
    if (!objects.find(c.object_id) || !objects.find(c.match))
      throw Error("matches name object " + std::to_string(c.object_id) + " or " + std::to_string(c.match) +
                  ", which the objects input lacks");
    pairs.emplace_back(std::min(c.object_id, c.match), std::max(c.object_id, c.match));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());

  std::vector<PairPose> result(pairs.size());
  ctx.progress().begin("registering moved objects", pairs.size());
  parallel_for(pairs.size(), ctx.threads(), [&](size_t k) {
    if (ctx.cancelled()) return;
    result[k] = reg(*objects.find(pairs[k].first), *objects.find(pairs[k].second));
    ctx.progress().advance();
  });
  ctx.progress().end();
  ctx.throw_if_cancelled();

  std::map<std::pair<int, int>, PairPose> by_pair;
  for (size_t k = 0; k < pairs.size(); ++k) by_pair[pairs[k]] = result[k];
  for (ObjectChange& c : out.objects) {
    if (c.status != ChangeStatus::moved || c.match < 0) continue;
    const bool forward = c.object_id < c.match;
    const PairPose& p = by_pair.at({std::min(c.object_id, c.match), std::max(c.object_id, c.match)});
    c.transform = (forward ? p.transform : p.transform.inverse()).matrix();
    c.has_transform = true;
    c.alternative_transforms.clear();
    for (const Eigen::Isometry3d& a : p.alternatives) c.alternative_transforms.push_back((forward ? a : a.inverse()).matrix());
  }
  return out;
}

}  // namespace lista::objreg
