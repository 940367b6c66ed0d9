// Metric learning of the descriptor network on shape identity, with the exact
// preprocessing of the plugin. Losses: normalised softmax over one learned
// proxy per training shape (cosine logits; in the spirit of NormFace /
// proxy-based metric learning), or batch-hard triplet (Hermans et al. 2017).
// Batch-hard triplet stays near its margin on partial scans (the hardest
// pairs are genuinely ambiguous) yet still ranks held-out shapes best; the
// proxy loss learns steadily but generalised less (docs/bench/descriptors.md).
#include "train.hpp"
#include "shape_sampler.hpp"

#include <lista_objfeat/canonical.hpp>
#include <lista_objfeat/descriptor_net.hpp>
#include <lista_objfeat/retrieval.hpp>

#include <lista/error.hpp>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

namespace lista::train {
namespace {

// Features of one view as the plugin computes them (fixed selection seed).
objfeat::Rows describe_all(objfeat::DescriptorNet& net, const objfeat::ViewSet& set) {
  const auto& c = net->config;
  objfeat::Rows out(long(set.views.size()), c.out);
  torch::NoGradGuard no_grad;
  net->eval();
  std::vector<objfeat::CanonicalCloud> clouds;
  // Views stand on z = 0 (docs/datasets.md): the floor is known.
  for (const auto& v : set.views)
    clouds.push_back(objfeat::make_canonical(v.points.xyz, objfeat::canonical_config(c), 0.f));
  const size_t chunk = 128;
  for (size_t b = 0; b < set.views.size(); b += chunk) {
    size_t e = std::min(set.views.size(), b + chunk);
    torch::Tensor d = objfeat::describe_clouds(net, clouds, b, e).contiguous();
    std::copy(d.data_ptr<float>(), d.data_ptr<float>() + d.numel(), out.data() + b * size_t(c.out));
  }
  net->train();
  return out;
}

void copy_weights(objfeat::DescriptorNet& from, objfeat::DescriptorNet& to) {
  torch::NoGradGuard no_grad;
  auto src = from->parameters(), dst = to->parameters();
  for (size_t i = 0; i < src.size(); ++i) dst[i].copy_(src[i]);
}

// A training sample: a random yaw, a random subset of points and a random
// voxel selection, so the network learns what survives partial observation;
// the floor (z = 0) with an estimate's error, or withheld.
objfeat::CanonicalCloud augmented(const objfeat::View& v, const objfeat::NetConfig& c, const TrainConfig& cfg,
                                  std::mt19937_64& rng) {
  std::uniform_real_distribution<float> u(0.f, 1.f);
  Eigen::Matrix3f r = Eigen::AngleAxisf(6.2832f * u(rng), Eigen::Vector3f::UnitZ()).toRotationMatrix();
  float keep = 0.4f + 0.6f * u(rng);
  std::normal_distribution<float> jitter(0.f, 0.004f);
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(v.points.xyz.size());
  for (const auto& p : v.points.xyz)
    if (u(rng) < keep) pts.push_back(r * p + Eigen::Vector3f(jitter(rng), jitter(rng), jitter(rng)));
  if (pts.size() < 8) pts = v.points.xyz;
  float floor = objfeat::kUnknownFloor;
  if (cfg.floor) {  // no draws without it: --no-floor runs reproduce the earlier models
    const float error = std::normal_distribution<float>(0.f, float(cfg.floor_noise))(rng);
    if (u(rng) >= float(cfg.floor_dropout)) floor = error;
  }
  return objfeat::make_canonical(pts, objfeat::canonical_config(c, rng()), floor);
}

}  // namespace

TrainResult train_descriptor(const objfeat::ViewSet& train, const objfeat::ViewSet& test, const TrainConfig& cfg) {
  auto t0 = std::chrono::steady_clock::now();
  torch::manual_seed(cfg.seed);
  torch::set_num_threads(cfg.threads);
  std::mt19937_64 rng(cfg.seed);

  if (cfg.lookalike_group > 1 && cfg.balance_sources)
    throw Error("look-alike groups and balanced sources are two ways to fill a batch: choose one");
  ShapeSampler sampler = cfg.lookalike_group > 1
                             ? ShapeSampler(train, cfg.instances_per_batch, cfg.lookalike_group, view_sizes(train),
                                            cfg.lookalike_share)
                             : ShapeSampler(train, cfg.instances_per_batch, cfg.balance_sources);
  const std::vector<int> instances = sampler.shapes();

  objfeat::NetConfig nc;
  nc.points = cfg.points;
  nc.grid = cfg.grid;
  nc.in = cfg.channels;
  nc.out = cfg.dim;
  nc.w1 = cfg.w1;
  nc.w2 = cfg.w2;
  nc.w3 = cfg.w3;
  nc.head = cfg.head;
  if (cfg.frame != "rectangle" && cfg.frame != "principal")
    throw Error("unknown frame '" + cfg.frame + "' (rectangle or principal)");
  nc.frame = cfg.frame == "rectangle" ? objfeat::YawFrame::bounding_rectangle : objfeat::YawFrame::principal_axis;
  if (!objfeat::valid_global_count(cfg.globals))
    throw Error("globals must be 0, " + std::to_string(objfeat::kExtentGlobals) + ", " +
                std::to_string(objfeat::kNoFloorGlobals) + " or " + std::to_string(objfeat::kShapeGlobals));
  nc.globals = cfg.globals;
  nc.floor = cfg.floor;
  objfeat::DescriptorNet net(nc);
  // The weight average starts as a copy of the initial weights.
  objfeat::DescriptorNet average(nc);
  copy_weights(net, average);
  // Proxy rows, one per training shape (only used by the proxy loss; they are
  // not part of the shipped weights).
  std::map<int, int64_t> proxy_of;
  for (int id : instances) proxy_of.emplace(id, int64_t(proxy_of.size()));
  // Small initial norm: proxies count by direction only, and Adam's steps have
  // a fixed size, so short proxies turn quickly (at norm ~4 they barely moved
  // in 500 steps and the loss crawled).
  torch::Tensor proxies = (0.05 * torch::randn({int64_t(proxy_of.size()), nc.out})).requires_grad_(true);
  auto params = net->parameters();
  if (cfg.loss == "proxy") params.push_back(proxies);
  else if (cfg.loss != "triplet") throw Error("unknown loss '" + cfg.loss + "' (proxy or triplet)");
  torch::optim::Adam opt(params, torch::optim::AdamOptions(cfg.lr));
  const int P = cfg.instances_per_batch, K = cfg.views_per_instance, B = P * K;
  TrainResult result;
  double running = 0.0;

  for (int step = 1; step <= cfg.steps; ++step) {
    // Cosine learning-rate decay to 5% of the start.
    double lr = cfg.lr * (0.05 + 0.95 * 0.5 * (1.0 + std::cos(M_PI * step / cfg.steps)));
    for (auto& g : opt.param_groups()) static_cast<torch::optim::AdamOptions&>(g.options()).lr(lr);

    const std::vector<int> shapes =
        cfg.lookalike_group > 1 && step < cfg.lookalike_from ? sampler.draw_uniform(rng) : sampler.draw(rng);
    std::vector<objfeat::CanonicalCloud> batch(static_cast<size_t>(B));
    std::vector<int64_t> labels(B), classes(B);
    for (int p = 0; p < P; ++p) {
      const auto& pool = sampler.views_of(shapes[size_t(p)]);
      for (int k = 0; k < K; ++k) {
        const objfeat::View& v = train.views[pool[rng() % pool.size()]];
        batch[size_t(p * K + k)] = augmented(v, nc, cfg, rng);
        labels[p * K + k] = p;
        classes[p * K + k] = proxy_of[shapes[size_t(p)]];
      }
    }
    torch::Tensor lab = torch::tensor(labels);
    torch::Tensor emb = objfeat::describe_clouds(net, batch, 0, batch.size());
    torch::Tensor loss;
    if (cfg.loss == "proxy") {
      torch::Tensor unit = torch::nn::functional::normalize(
          proxies, torch::nn::functional::NormalizeFuncOptions().dim(1).eps(1e-8));
      loss = torch::nn::functional::cross_entropy(cfg.scale * emb.mm(unit.t()), torch::tensor(classes));
    } else {
      torch::Tensor dist = torch::cdist(emb, emb);
      torch::Tensor same = lab.unsqueeze(0).eq(lab.unsqueeze(1));
      torch::Tensor hardest_pos = (dist * same.to(torch::kFloat)).amax(1);
      torch::Tensor hardest_neg = dist.masked_fill(same, 1e4).amin(1);
      loss = torch::relu(hardest_pos - hardest_neg + cfg.margin).mean();
    }
    opt.zero_grad();
    loss.backward();
    opt.step();
    if (cfg.ema > 0.0) {
      // Warm-up so the first steps' random weights fade quickly.
      const double decay = std::min(cfg.ema, (1.0 + step) / (10.0 + step));
      torch::NoGradGuard no_grad;
      auto src = net->parameters(), dst = average->parameters();
      for (size_t i = 0; i < src.size(); ++i) dst[i].mul_(decay).add_(src[i].detach(), 1.0 - decay);
    }
    running = 0.98 * running + 0.02 * loss.item<double>();

    if (step % cfg.eval_every == 0 || step == cfg.steps) {
      double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::string eval;
      if (!test.views.empty()) {
        std::vector<int> tl;
        for (const auto& v : test.views) tl.push_back(v.label);
        auto s = objfeat::score_retrieval(describe_all(cfg.ema > 0.0 ? average : net, test), tl, cfg.seed);
        result.test_top1 = s.top1;
        result.test_map = s.map;
        char buf[128];
        std::snprintf(buf, sizeof buf, "  held-out top1 %.3f mAP %.3f", s.top1, s.map);
        eval = buf;
      }
      std::fprintf(stderr, "step %5d  loss %.4f  lr %.2e  %.0fs%s\n", step, running, lr, secs, eval.c_str());
    }
  }
  if (cfg.ema > 0.0) copy_weights(average, net);
  net->eval();
  save_weights(net, cfg.out);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

void prepare_output(const std::string& out, bool overwrite) {
  const std::filesystem::path path(out);
  std::error_code ec;
  if (out.empty() || !path.has_filename()) throw Error("--out '" + out + "' names no file; give the weights file to write");
  if (std::filesystem::exists(path, ec)) {
    if (!std::filesystem::is_regular_file(path, ec))
      throw Error("--out " + out + " exists and is not a regular file; choose another --out");
    if (!overwrite) throw Error("--out " + out + " exists; add --overwrite to replace it (and its .sha256)");
  }
  if (std::filesystem::exists(out + ".sha256", ec) && !std::filesystem::is_regular_file(out + ".sha256", ec))
    throw Error(out + ".sha256 exists and is not a regular file; choose another --out");
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) throw Error("cannot make the folder of '" + out + "': " + ec.message() + "; choose another --out");
  const std::string probe = out + ".tmp";
  if (!std::ofstream(probe)) throw Error("cannot write '" + probe + "': choose another --out");
  std::filesystem::remove(probe, ec);
}

}  // namespace lista::train
