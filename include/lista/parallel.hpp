// lista::parallel_for: the one work-sharing loop of the SDK, for stages that
// spread independent items (object pairs, keyframes, files) over
// Context::threads(). Indices are handed out one at a time (items often
// differ a lot in cost); the first exception stops handing out work and is
// rethrown in the caller once every thread has finished. Deterministic
// results are the caller's job: write result i into slot i.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace lista {

template <class Fn>
void parallel_for(size_t count, int threads, Fn&& fn) {
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (size_t i; (i = next.fetch_add(1)) < count;) {
      try {
        fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = count;  // stop handing out work
      }
    }
  };
  const size_t n = std::min<size_t>(static_cast<size_t>(std::max(1, threads)), count);
  std::vector<std::thread> pool;
  for (size_t t = 1; t < n; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace lista
