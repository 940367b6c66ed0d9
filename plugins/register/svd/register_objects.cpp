#include "register_objects.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <atomic>
#include <exception>
#include <map>
#include <mutex>
#include <thread>
#include <utility>

namespace lista::registration {

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

  std::vector<Eigen::Isometry3d> result(pairs.size());
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  ctx.progress().begin("registering moved objects", pairs.size());
  auto worker = [&] {
    for (size_t k; (k = next++) < pairs.size();) {
      if (ctx.cancelled()) return;
      try {
        result[k] = reg(*objects.find(pairs[k].first), *objects.find(pairs[k].second));
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
      ctx.progress().advance();
    }
  };
  const int n_threads = std::max(1, std::min<int>(ctx.threads(), static_cast<int>(pairs.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < n_threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  ctx.progress().end();
  ctx.throw_if_cancelled();
  if (failure) std::rethrow_exception(failure);

  std::map<std::pair<int, int>, Eigen::Isometry3d> by_pair;
  for (size_t k = 0; k < pairs.size(); ++k) by_pair[pairs[k]] = result[k];
  for (ObjectChange& c : out.objects) {
    if (c.status != ChangeStatus::moved || c.match < 0) continue;
    const bool forward = c.object_id < c.match;
    const Eigen::Isometry3d& t = by_pair.at({std::min(c.object_id, c.match), std::max(c.object_id, c.match)});
    c.transform = (forward ? t : t.inverse()).matrix();
    c.has_transform = true;
  }
  return out;
}

}  // namespace lista::registration
