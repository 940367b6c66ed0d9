// volumetric.openvdb and volumetric.octomap agree on the synthetic two-room
// scene: the change points either finds, the other finds too (98 %).
#include <lista/basic_context.hpp>
#include <lista_core/loader.hpp>
#include <lista_core/registry.hpp>
#include <lista_raycast/scene_checks.hpp>
#include <lista_raycast/synthetic_scene.hpp>

#include <gtest/gtest.h>

using namespace lista;

namespace {

MissionPoints run_backend(const core::Registry& registry, const std::string& name, const MissionSet& missions) {
  const core::RegisteredStage* stage = registry.find(name);
  if (!stage) throw Error("no stage " + name + " in " LISTA_PLUGIN_DIR);
  BasicContext ctx("diff", 2);
  Inputs in;
  in.set("missions", Data::make(missions));
  return stage->factory(Params::defaults(stage->info.params))->run(in, ctx).at("changes").as<MissionPoints>();
}

}  // namespace

TEST(VolumetricBackends, OpenVdbAgreesWithOctomap) {
  core::Registry registry;
  core::load_plugins(registry, {LISTA_PLUGIN_DIR});
  raycast::SyntheticSceneConfig c;  // several scans per spot: occupancy needs repeated evidence
  c.rings = 16;
  c.columns = 360;
  c.scans_per_position = 4;
  const MissionSet scene = raycast::make_synthetic_scene(c);
  const MissionPoints vdb = run_backend(registry, "volumetric.openvdb", scene);
  const MissionPoints oct = run_backend(registry, "volumetric.octomap", scene);
  size_t both = 0, either = 0;
  for (size_t m = 0; m < 2; ++m) {
    const auto a = raycast::provenance(vdb.sets[m]), b = raycast::provenance(oct.sets[m]);
    for (const auto& p : a) both += b.count(p);
    either += a.size() + b.size();
  }
  either -= both;
  ASSERT_GT(either, 0u);
  EXPECT_GE(static_cast<double>(both) / either, 0.98) << both << " of " << either;
}
