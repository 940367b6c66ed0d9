// Helpers for describe.* plugin tests (header-only, no test framework):
// instantiate the plugin's one stage from its manifest and run it on
// synthetic objects.
#pragma once

#include <lista/basic_context.hpp>
#include <lista/data.hpp>
#include <lista/plugin.hpp>
#include <lista_objfeat/synthetic.hpp>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

namespace lista_plugin_detail {
const ::lista::PluginManifest* manifest();
}

namespace lista::objfeat::testing {

struct Capture : Registrar {
  std::vector<std::pair<StageInfo, StageFactory>> stages;
  void add(StageInfo i, StageFactory f) override { stages.emplace_back(std::move(i), std::move(f)); }
};

// The linked plugin's first stage, with defaults overridden by `set`.
inline std::unique_ptr<Stage> make_stage(const std::vector<std::pair<std::string, ParamValue>>& set = {}) {
  Capture cap;
  lista_plugin_detail::manifest()->register_stages(cap);
  Params p = Params::defaults(cap.stages.at(0).first.params);
  for (const auto& [k, v] : set) p.set(k, v);
  return cap.stages.at(0).second(p);
}

inline Object object_from(int id, const std::vector<Eigen::Vector3f>& xyz, bool with_intensity = false) {
  Object o;
  o.id = id;
  o.points.xyz = xyz;
  o.points.scan.assign(xyz.size(), 0);
  o.points.index.resize(xyz.size());
  for (size_t i = 0; i < xyz.size(); ++i) o.points.index[i] = uint32_t(i);
  if (with_intensity)  // a painted band, so intensity has gradients
    for (const auto& p : xyz) o.points.intensity.push_back(std::fmod(std::abs(p.z()) * 3.f, 1.f) > 0.5f ? 0.8f : 0.2f);
  o.update_geometry();
  return o;
}

inline DescriptorSet describe(Stage& stage, const ObjectSet& set, int threads = 1) {
  Inputs in;
  in.set("objects", Data::make(set));
  BasicContext ctx("test", threads);
  return stage.run(in, ctx).at("descriptors").as<DescriptorSet>();
}

// `shapes` random shapes, two views each (objects 2s and 2s+1).
inline ObjectSet two_views_each(int shapes, uint64_t seed, bool with_intensity = false) {
  std::mt19937_64 rng(seed);
  ObjectSet set;
  for (int s = 0; s < shapes; ++s) {
    Shape shape = random_shape(rng);
    for (int v = 0; v < 2; ++v)
      set.objects.push_back(object_from(2 * s + v, render_view(shape, 0.9f * float(s + 3 * v), {float(v), 0.f}, rng),
                                        with_intensity));
  }
  return set;
}

// Mean distance between the two views of one shape, and between views of different shapes.
inline std::pair<double, double> within_between(const DescriptorSet& d) {
  double within = 0, between = 0;
  int nw = 0, nb = 0;
  for (long i = 0; i < d.values.rows(); ++i)
    for (long j = i + 1; j < d.values.rows(); ++j) {
      double dist = (d.values.row(i) - d.values.row(j)).norm();
      if (i / 2 == j / 2) { within += dist; ++nw; } else { between += dist; ++nb; }
    }
  return {within / std::max(nw, 1), between / std::max(nb, 1)};
}

}  // namespace lista::objfeat::testing
