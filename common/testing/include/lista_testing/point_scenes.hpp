// Test helpers shared by the filter.* and segment.* plugin tests (header
// only; each test links just its own plugin): synthetic clouds, and running
// the plugin's stage through its exported manifest, as the core would.
#pragma once

#include <lista/basic_context.hpp>
#include <lista/data.hpp>
#include <lista_testing/plugin_stage.hpp>

#include <map>
#include <set>
#include <random>

namespace test_support {

// Runs stage `name` with default params overridden by `set`, one input port;
// what it logged and recorded goes to `context` when given.
inline lista::Outputs run_stage(const std::string& name, const std::string& port, lista::Data input,
                                const std::map<std::string, lista::ParamValue>& set = {},
                                int threads = 2, lista::BasicContext* context = nullptr) {
  auto stage = lista::plugin_test::make_stage(name, set);
  lista::Inputs in;
  in.set(port, std::move(input));
  lista::BasicContext own("test", threads, 7);
  lista::BasicContext& ctx = context ? *context : own;
  return stage->run(in, ctx);
}

// Points on the surface of an axis-aligned box, spacing `step`, with
// provenance scan = `scan`, index = running number.
inline void add_box_surface(lista::PointSet& s, Eigen::Vector3f lo, Eigen::Vector3f hi, float step,
                            uint32_t scan = 0) {
  const Eigen::Vector3i n = ((hi - lo) / step).array().round().cast<int>();
  for (int i = 0; i <= n.x(); ++i)
    for (int j = 0; j <= n.y(); ++j)
      for (int k = 0; k <= n.z(); ++k) {
        const bool on = i == 0 || i == n.x() || j == 0 || j == n.y() || k == 0 || k == n.z();
        if (!on) continue;
        s.xyz.push_back(lo + step * Eigen::Vector3f(float(i), float(j), float(k)));
        s.scan.push_back(scan);
        s.index.push_back(uint32_t(s.index.size()));
      }
}

// Uniform random points in a ball, for blob tests.
inline void add_blob(lista::PointSet& s, Eigen::Vector3f centre, float radius, int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int k = 0; k < n;) {
    Eigen::Vector3f d(u(rng), u(rng), u(rng));
    if (d.squaredNorm() > 1.f) continue;
    s.xyz.push_back(centre + radius * d);
    s.scan.push_back(0);
    s.index.push_back(uint32_t(s.index.size()));
    ++k;
  }
}

inline void add_point(lista::PointSet& s, Eigen::Vector3f p) {
  s.xyz.push_back(p);
  s.scan.push_back(0);
  s.index.push_back(uint32_t(s.index.size()));
}

inline lista::MissionPoints missions(std::vector<lista::PointSet> sets) {
  lista::MissionPoints mp;
  for (size_t i = 0; i < sets.size(); ++i) mp.missions.push_back("m" + std::to_string(i));
  mp.sets = std::move(sets);
  return mp;
}

}  // namespace test_support
