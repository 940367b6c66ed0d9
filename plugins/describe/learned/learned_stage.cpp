// describe.learned: one L2-normalised descriptor per object from the learned
// PointNet-style network (common/objfeat). Preprocessing (centre, yaw
// canonicalisation, voxel resampling to a fixed size) is shared with
// lista-train, so the plugin sees exactly what the network was trained on.
#include "model_path.hpp"

#include <lista/parallel.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>
#include <lista_objfeat/canonical.hpp>
#include <lista_objfeat/descriptor_net.hpp>

#include <algorithm>
#include <filesystem>

namespace lista::describe {
namespace {

// Fixed so the descriptor is a pure function of the object's points (the same
// object gives the same row in every run, whatever the run's seed).
constexpr uint64_t kSelectionSeed = objfeat::CanonicalConfig{}.seed;

struct LearnedConfig {
  std::string weights;
  int batch = 64;
  int samples = 4;
};

const ParamTable<LearnedConfig>& param_table() {
  using C = LearnedConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("weights", &C::weights, "weights file (empty: the shipped model, see doc)");
    t.bind("batch", &C::batch, "objects per network call").range(1, 4096);
    t.bind("samples", &C::samples,
           "voxel-cell selections per object whose descriptors are averaged (1: one fixed selection)")
        .range(1, 64);
  });
}

class LearnedStage : public Stage {
 public:
  explicit LearnedStage(const Params& p) : c_(param_table().read(p)) {
    std::string path = c_.weights;
    if (path.empty()) path = default_weights_path();
    weights_path_ = std::filesystem::absolute(path).lexically_normal().string();
    net_ = objfeat::load_weights(path, &weights_sha256_);  // throws a one-line lista::Error
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "describe.learned";
    i.version = "1.0.0";
    i.summary = "learned yaw-invariant object descriptor (PointNet-style, libtorch)";
    i.doc =
        "A small PointNet-style network (libtorch, trained by lista-train) on each object's yaw-canonical, "
        "voxel-resampled points and shape globals, heights from its floor when known: one L2-normalised row "
        "per object. Weights: the weights parameter, else $LISTA_MODEL_DIR, else the models/ folder; a "
        "missing or corrupt file is an error. "
        "Details: docs/descriptors.md, \"describe.learned\".";
    i.inputs = {{"objects", "objects", "objects to describe"}};
    i.outputs = {{"descriptors", "descriptors", "one unit-norm row per object"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const ObjectSet& objects = in.get<ObjectSet>("objects");
    const objfeat::NetConfig& cfg = net_->config;
    const size_t n = objects.objects.size();
    for (const Object& o : objects.objects)
      if (o.points.empty()) throw Error("object " + std::to_string(o.id) + " has no points to describe");

    // Preprocessing is plain C++: spread it over the stage's threads.
    // Object i's selections are clouds[i * S .. i * S + S - 1].
    const size_t S = size_t(c_.samples);
    std::vector<objfeat::CanonicalCloud> clouds(n * S);
    parallel_for(n, ctx.threads(), [&](size_t i) {
      const Object& o = objects.objects[i];
      auto samples = objfeat::make_canonical_samples(o.points.xyz, objfeat::canonical_config(cfg, kSelectionSeed),
                                                     c_.samples, o.floor_z);
      std::move(samples.begin(), samples.end(), clouds.begin() + ptrdiff_t(i * S));
    });

    DescriptorSet out;
    out.method = "describe.learned";
    out.normalized = true;
    out.values.resize(long(n), cfg.out);
    torch::NoGradGuard no_grad;
    torch::set_num_threads(ctx.threads());
    for (size_t begin = 0; begin < n; begin += size_t(c_.batch)) {
      ctx.throw_if_cancelled();
      size_t end = std::min(n, begin + size_t(c_.batch));
      torch::Tensor d = objfeat::mean_of_samples(objfeat::describe_clouds(net_, clouds, begin * S, end * S), c_.samples);
      std::copy(d.data_ptr<float>(), d.data_ptr<float>() + d.numel(), out.values.data() + begin * size_t(cfg.out));
    }
    for (const Object& o : objects.objects) out.object_ids.push_back(o.id);
    ctx.record("objects", double(n));
    // The pipeline shows weights = "" for the shipped model: the report says which file it was.
    ctx.note("weights", weights_path_);
    ctx.note("weights_sha256", weights_sha256_);
    return Outputs::of("descriptors", std::move(out));
  }

 private:
  const LearnedConfig c_;
  std::string weights_path_, weights_sha256_;
  objfeat::DescriptorNet net_{nullptr};
};

}  // namespace
}  // namespace lista::describe

LISTA_STAGE_PLUGIN(lista::describe::LearnedStage::info, lista::describe::LearnedStage)
