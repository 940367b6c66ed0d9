// lista-train's loop on a tiny synthetic set: same seed, same weights byte for
// byte; the loss learns something (retrieval on the training views beats the
// untrained net; the held-out part of so tiny a set is too noisy to judge).
#include "train.hpp"

#include <lista_objfeat/descriptor_net.hpp>

#include <lista/error.hpp>

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

lista::train::TrainConfig tiny(const std::string& out, int steps) {
  lista::train::TrainConfig c;
  c.steps = steps;
  c.instances_per_batch = 8;
  c.views_per_instance = 3;
  c.points = 64;
  c.w1 = 16;
  c.w2 = 32;
  c.w3 = 64;
  c.head = 32;
  c.threads = 1;
  c.eval_every = steps;
  c.seed = 4;
  c.loss = "triplet";
  c.out = out;
  return c;
}

// 16 synthetic shapes x 4 views, 4 shapes held out, and a fresh temp
// folder for weights files (removed with the fixture).
class ListaTrainTiny : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("lista_train_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
           std::to_string(::getpid()));
    fs::create_directories(dir);
    lista::objfeat::split_by_shape(lista::objfeat::synthetic_views(16, 4, 2), 0.25, 2, train, test);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string file(const std::string& name) const { return (dir / name).string(); }

  fs::path dir;
  lista::objfeat::ViewSet train, test;
};

TEST_F(ListaTrainTiny, SameSeedSameWeightsAndTrainingHelps) {
  ASSERT_EQ(test.views.size(), 16u);  // 4 of 16 shapes held out, 4 views each

  const std::string a = file("a.bin"), b = file("b.bin"), c = file("c.bin");
  lista::train::train_descriptor(train, test, tiny(a, 30));
  lista::train::train_descriptor(train, test, tiny(b, 30));
  EXPECT_EQ(read_all(a), read_all(b));
  EXPECT_TRUE(fs::exists(a + ".sha256"));
  // The weights file records the preprocessing the network was trained with.
  const lista::objfeat::NetConfig saved = lista::objfeat::load_weights(a)->config;
  EXPECT_EQ(saved.frame, lista::objfeat::YawFrame::bounding_rectangle);
  EXPECT_EQ(saved.globals, lista::objfeat::kShapeGlobals);
  EXPECT_EQ(saved.points, 64);
  EXPECT_TRUE(saved.floor);
  // Training must teach the per-point network. Without the extents in the
  // head (on these synthetic boxes the extents alone already rank well
  // untrained), the learned part is all there is.
  auto per_point = [&](int steps) {
    auto cfg = tiny(c, steps);
    cfg.globals = 0;
    return lista::train::train_descriptor(train, train, cfg);
  };
  auto trained = per_point(150), untrained = per_point(1);
  EXPECT_GT(trained.test_map, untrained.test_map + 0.05) << trained.test_map << " vs " << untrained.test_map;
  EXPECT_EQ(lista::objfeat::load_weights(c)->config.globals, 0);
  // With the extents, training still improves the ranking.
  auto with_globals = lista::train::train_descriptor(train, train, tiny(c, 150));
  auto with_globals_untrained = lista::train::train_descriptor(train, train, tiny(c, 1));
  EXPECT_GT(with_globals.test_map, with_globals_untrained.test_map);
  EXPECT_THROW(lista::train::train_descriptor(test, test, tiny(c, 1)), lista::Error);  // 4 shapes < 8 per batch
}

// The averaged weights are what is saved: deterministic, not the last step's
// weights, and still trained.
TEST_F(ListaTrainTiny, WeightAverageIsSavedDeterministicallyAndLearns) {
  const std::string plain = file("plain.bin"), a = file("a.bin"), b = file("b.bin");
  auto averaged = [&](const std::string& out, int steps) {
    auto cfg = tiny(out, steps);
    cfg.globals = 0;
    cfg.ema = 0.9;
    return lista::train::train_descriptor(train, train, cfg);
  };
  auto cfg = tiny(plain, 150);
  cfg.globals = 0;
  lista::train::train_descriptor(train, train, cfg);
  auto trained = averaged(a, 150);
  averaged(b, 150);
  EXPECT_EQ(read_all(a), read_all(b));
  EXPECT_NE(read_all(a), read_all(plain));
  auto untrained = averaged(b, 1);
  EXPECT_GT(trained.test_map, untrained.test_map + 0.05) << trained.test_map << " vs " << untrained.test_map;
}

// Weights of the earlier four-global layout still train, load and read only
// the first four globals; anything else is refused before training.
TEST_F(ListaTrainTiny, FourGlobalWeightsReadTheFirstFour) {
  const std::string out = file("g4.bin");
  auto cfg = tiny(out, 20);
  cfg.globals = lista::objfeat::kExtentGlobals;
  lista::train::train_descriptor(train, test, cfg);
  lista::objfeat::DescriptorNet net = lista::objfeat::load_weights(out);
  ASSERT_EQ(net->config.globals, lista::objfeat::kExtentGlobals);
  net->eval();
  torch::NoGradGuard no_grad;
  std::vector<lista::objfeat::CanonicalCloud> clouds = {
      lista::objfeat::make_canonical(train.views.front().points.xyz, lista::objfeat::canonical_config(net->config))};
  clouds.push_back(clouds.front());
  for (int g = lista::objfeat::kExtentGlobals; g < lista::objfeat::kShapeGlobals; ++g) clouds.back().globals[size_t(g)] += 5.f;
  clouds.push_back(clouds.front());
  clouds.back().globals[0] += 5.f;
  const torch::Tensor rows = lista::objfeat::describe_clouds(net, clouds, 0, clouds.size());
  EXPECT_TRUE(torch::equal(rows[0], rows[1]));   // globals 4-8 are not read
  EXPECT_FALSE(torch::equal(rows[0], rows[2]));  // global 0 is
  cfg.globals = 5;
  EXPECT_THROW(lista::train::train_descriptor(train, test, cfg), lista::Error);
}

// Without the floor (--no-floor) the file says so, and the random draws of
// the floor's augmentation are not made: the same seed trains the same
// weights as before the floor existed, whatever floor_dropout says. With
// it, withholding the floor from every sample trains other weights than
// giving it to every sample.
TEST_F(ListaTrainTiny, NoFloorRunsSkipTheFloorsDrawsAndRecordIt) {
  auto run = [&](const std::string& name, bool floor, double dropout) {
    auto cfg = tiny(file(name), 20);
    cfg.globals = lista::objfeat::kNoFloorGlobals;
    cfg.floor = floor;
    cfg.floor_dropout = dropout;
    lista::train::train_descriptor(train, test, cfg);
    return read_all(file(name));
  };
  const std::string a = run("a.bin", false, 0.2), b = run("b.bin", false, 0.9);
  EXPECT_EQ(a, b);
  EXPECT_FALSE(lista::objfeat::load_weights(file("a.bin"))->config.floor);
  const std::string always = run("c.bin", true, 0.0), never = run("d.bin", true, 1.0);
  EXPECT_TRUE(lista::objfeat::load_weights(file("c.bin"))->config.floor);
  EXPECT_NE(always, never);
}

}  // namespace

TEST(ListaTrain, OutputFolderIsMadeAndAnUnwritableOutIsAnErrorBeforeTraining) {
  const fs::path dir = fs::temp_directory_path() / ("lista-train-out-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string nested = (dir / "a" / "b" / "w.bin").string();
  lista::train::prepare_output(nested, false);
  EXPECT_TRUE(fs::is_directory(dir / "a" / "b"));
  EXPECT_FALSE(fs::exists(nested + ".tmp"));  // the probe is gone
  // A regular file where a folder should be: one clear error naming the path.
  std::ofstream(dir / "file") << "x";
  auto refused = [](const std::string& out, bool overwrite, const std::string& text) {
    try {
      lista::train::prepare_output(out, overwrite);
      ADD_FAILURE() << "accepted " << out;
    } catch (const lista::Error& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  refused((dir / "file" / "w.bin").string(), false, "file/w.bin");
  // An existing weights file (the shipped model, say) only with --overwrite;
  // a folder or a device never.
  refused((dir / "file").string(), false, "exists; add --overwrite to replace it");
  EXPECT_NO_THROW(lista::train::prepare_output((dir / "file").string(), true));
  refused((dir / "a").string(), true, "exists and is not a regular file");
  refused("/dev/null", true, "exists and is not a regular file");
  refused("", true, "names no file");
  fs::remove_all(dir);
}

// A diverged network (NaN weights) is not saved: training fails instead of
// shipping a model every pipeline would then run on; nothing is left behind.
TEST(ListaTrain, NonFiniteWeightsAreNotSaved) {
  const fs::path dir = fs::temp_directory_path() / ("lista-train-nan-" + std::to_string(getpid()));
  fs::create_directories(dir);
  lista::objfeat::NetConfig c;
  lista::objfeat::DescriptorNet net(c);
  {
    torch::NoGradGuard no_grad;
    net->named_parameters().begin()->value().fill_(std::numeric_limits<float>::quiet_NaN());
  }
  const std::string out = (dir / "w.bin").string();
  EXPECT_THROW(lista::objfeat::save_weights(net, out), lista::Error);
  EXPECT_TRUE(fs::is_empty(dir)) << "no weights, sidecar or .tmp";
  fs::remove_all(dir);
}

TEST_F(ListaTrainTiny, LookalikeGroupsTrainFromTheirFirstStepAndCannotBeCombinedWithBalancedSources) {
  auto cfg = tiny(file("plain.bin"), 30);
  lista::train::train_descriptor(train, test, cfg);
  cfg.lookalike_group = 2;
  cfg.lookalike_from = 31;  // never: exactly the plain run
  cfg.out = file("late.bin");
  lista::train::train_descriptor(train, test, cfg);
  EXPECT_EQ(read_all(file("late.bin")), read_all(file("plain.bin")));
  cfg.lookalike_from = 15;
  cfg.out = file("groups.bin");
  const auto r = lista::train::train_descriptor(train, test, cfg);
  EXPECT_NE(read_all(file("groups.bin")), read_all(file("plain.bin")));
  EXPECT_GT(r.test_top1, 0.0);
  cfg.balance_sources = true;
  cfg.out = file("both.bin");
  EXPECT_THROW(lista::train::train_descriptor(train, test, cfg), lista::Error);
  EXPECT_FALSE(fs::exists(file("both.bin")));
}
