// All describe.* plugins, loaded from their shared libraries the way the
// benchmark (and the core) load them: same ports and port types, so the
// grouping stage never cares which one a pipeline uses, and each gives one
// unit row per object on the same synthetic objects.
#include <lista_bench/stage_finder.hpp>

#include <lista/basic_context.hpp>
#include <lista/data.hpp>
#include <lista_objfeat/synthetic.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

namespace {

using namespace lista;

// describe.learned is left out when libtorch is missing (see its CMakeLists)
// or, in a checkout without models/, when no weights are shipped.
std::vector<std::string> present_plugins() {
  std::vector<std::string> out;
  for (std::string name : {"describe.learned", "describe.esf", "describe.shot", "describe.rift"}) {
    std::string file = "liblista_" + name + ".so";
    file[file.find('.')] = '_';
    if (!std::filesystem::exists(std::filesystem::path(LISTA_PLUGIN_DIR) / file)) continue;
    if (name == "describe.learned" &&
        !std::filesystem::exists(std::string(LISTA_SOURCE_DIR) + "/models/describe-learned.bin"))
      continue;
    out.push_back(name);
  }
  return out;
}

ObjectSet small_set() {
  std::mt19937_64 rng(17);
  ObjectSet set;
  for (int s = 0; s < 3; ++s) {
    auto shape = objfeat::random_shape(rng);
    Object o;
    o.id = 10 + s;
    o.points.xyz = objfeat::render_view(shape, 0.3f * float(s), {float(s), 0.f}, rng);
    o.points.scan.assign(o.points.size(), 0);
    o.points.index.resize(o.points.size());
    for (size_t i = 0; i < o.points.size(); ++i) o.points.index[i] = uint32_t(i);
    o.update_geometry();
    set.objects.push_back(std::move(o));
  }
  return set;
}

TEST(DescriptorPlugins, AllShareOnePortTypeAndGiveUnitRowsPerObject) {
  auto names = present_plugins();
  ASSERT_GE(names.size(), 3u) << "the hand-crafted describe.* plugins are not built in " << LISTA_PLUGIN_DIR;
  const ObjectSet set = small_set();
  const bench::StageFinder finder({LISTA_PLUGIN_DIR}, false);
  for (const auto& name : names) {
    SCOPED_TRACE(name);
    const core::RegisteredStage& s = finder.find(name);
    EXPECT_EQ(s.info.kind(), "describe");
    ASSERT_EQ(s.info.inputs.size(), 1u);
    ASSERT_EQ(s.info.outputs.size(), 1u);
    EXPECT_EQ(s.info.inputs[0].name, "objects");
    EXPECT_EQ(s.info.inputs[0].type, "objects");
    EXPECT_EQ(s.info.outputs[0].name, "descriptors");
    EXPECT_EQ(s.info.outputs[0].type, "descriptors");

    auto stage = s.factory(Params::defaults(s.info.params));
    Inputs in;
    in.set("objects", Data::make(set));
    BasicContext ctx("test", 1);
    const Outputs out = stage->run(in, ctx);
    const auto& d = out.at("descriptors").as<DescriptorSet>();
    EXPECT_EQ(d.method, name);
    EXPECT_TRUE(d.normalized);
    ASSERT_EQ(d.values.rows(), 3);
    EXPECT_EQ(d.object_ids, (std::vector<int>{10, 11, 12}));
    for (long i = 0; i < 3; ++i) EXPECT_NEAR(d.values.row(i).norm(), 1.f, 1e-4f);
    EXPECT_EQ(contract_problem(d, set), "");
  }
}

TEST(DescriptorPlugins, UnknownPluginIsAClearErrorNamingTheNearestOne) {
  const bench::StageFinder finder({LISTA_PLUGIN_DIR}, false);
  try {
    finder.find("describe.shoot");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown plugin 'describe.shoot' (did you mean 'describe.shot'?)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
