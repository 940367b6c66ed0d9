// Metric learning of the describe.learned network on instance identity.
#pragma once

#include <lista_objfeat/canonical.hpp>
#include <lista_objfeat/views.hpp>

#include <string>

namespace lista::train {

struct TrainConfig {
  int steps = 1500;
  int instances_per_batch = 16;  // P
  int views_per_instance = 4;    // K (batch = P x K)
  double lr = 1e-3;
  // "triplet": batch-hard triplet loss (the shipped model); "proxy":
  // normalised softmax over one learned proxy per training shape (every
  // sample is pulled to its proxy and pushed from all others). On our views
  // the proxy loss scored lower on held-out shapes (docs/bench/descriptors.md).
  std::string loss = "triplet";
  double scale = 16.0;           // proxy logits = scale x cosine (temperature 1/scale)
  double margin = 0.3;           // triplet margin on unit descriptors
  int dim = 16;
  int points = 128;
  int grid = 24;  // voxel cells along the largest extent (canonical.hpp)
  // Canonical channels per point (canonical.hpp): 6 adds the height above the
  // lowest point; 5 is the previous models' input.
  int channels = objfeat::kCanonicalChannels;
  // Shared per-point MLP widths and head width (descriptor_net.hpp). Small on
  // purpose: about 6x less arithmetic than 256 points through 64-128-256/256
  // (2.5x less wall time per step under load), so training fits the time
  // budget on 2 loaded cores and inference stays well under 5 ms per object.
  int w1 = 32, w2 = 64, w3 = 128, head = 128;
  // Yaw frame ("rectangle": minimum-perimeter footprint rectangle; "principal":
  // principal axis, the first model's) and how many shape globals the head
  // sees (canonical.hpp); both are recorded in the weights file.
  std::string frame = "rectangle";
  // Shape globals the head reads: 0, objfeat::kExtentGlobals, kNoFloorGlobals or kShapeGlobals.
  int globals = objfeat::kShapeGlobals;
  // Heights measured from the floor (canonical.hpp; views stand on z = 0,
  // docs/datasets.md). A `floor_dropout` share of the training samples gets
  // no floor, so the model also describes objects whose floor no stage
  // measured (from the lowest point, as the models before it); the others
  // get the floor with `floor_noise` (metres, standard deviation) of error,
  // what a floor estimate from a map is off by.
  bool floor = true;
  double floor_dropout = 0.2;
  double floor_noise = 0.01;
  // Exponential moving average of the weights (Polyak averaging); 0 = off.
  // The averaged weights are the ones evaluated and saved: they sit nearer
  // the middle of the region the last, noisy steps wander in.
  double ema = 0.0;
  // Every shape source gets an equal share of each batch (shape_sampler.hpp);
  // off: shapes are drawn uniformly, whatever their source.
  bool balance_sources = false;
  // Look-alike groups per batch (shape_sampler.hpp): shapes come in groups of
  // this many of nearly one size; 1 = off (uniform). Not with balance_sources.
  int lookalike_group = 1;
  // Share of each batch's slots in groups, and the first step that draws
  // groups (uniform batches before it). Hard batches from the first step
  // collapse batch-hard training (loss = margin throughout, held-out top-1 0.17):
  // the network must first learn coarse shape from uniform batches.
  double lookalike_share = 1.0;
  int lookalike_from = 0;
  uint64_t seed = 1;
  int threads = 1;
  int eval_every = 500;
  std::string out;  // required: the shipped model is replaced only on purpose
};

struct TrainResult {
  double seconds = 0.0;
  double test_top1 = 0.0, test_map = 0.0;
};

TrainResult train_descriptor(const objfeat::ViewSet& train, const objfeat::ViewSet& test, const TrainConfig& config);

// Makes the weights file's folder and checks that the file can be written,
// so that a bad --out fails before minutes of training, not after. An
// existing file is replaced only with `overwrite`; a folder, a device or
// anything else that is not a regular file never is. Throws lista::Error
// naming the path.
void prepare_output(const std::string& out, bool overwrite);

}  // namespace lista::train
