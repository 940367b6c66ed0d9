// The learned object descriptor network (libtorch) and its weights file.
// Include only from .cpp files that must see torch (the describe.learned
// plugin and lista-train); everything else uses canonical.hpp.
//
// Architecture: a PointNet-style shared per-point MLP over the canonical
// cloud (canonical.hpp: yaw-canonical xyz + radius + distance, and in 6-channel
// models the height above the lowest point), max- and
// mean-pooled (order-invariant; max keeps salient parts, mean is stable
// under partial views), joined by the shape globals (canonical.hpp: sizes
// that the resampled cells blur), then an MLP head to `out` dims,
// L2-normalised.
//
// Weights file (little-endian): "LISTADN2", 11 x uint32 config
// (points grid in w1 w2 w3 head out frame globals floor), uint32 tensor
// count, then per tensor uint32 name length, name, uint32 element count,
// float32 data. "LISTADN1" files (the first model: 9 x uint32, no frame and
// globals fields) load as principal-axis frame without globals. `floor` (1:
// heights from the floor when known, canonical.hpp) was a reserved 0 before
// 2026-11-26, so earlier files load as models without the floor.
// Next to it, "<file>.sha256" holds the SHA-256 (sha256sum format).
#pragma once

#include <lista_objfeat/canonical.hpp>

#include <torch/torch.h>

#include <cstdint>
#include <string>

namespace lista::objfeat {

struct NetConfig {
  int points = 256, grid = 24;
  // in: canonical channels read per point (kFirstModelChannels or kCanonicalChannels).
  int in = kCanonicalChannels, w1 = 64, w2 = 128, w3 = 256, head = 256, out = 16;
  YawFrame frame = YawFrame::bounding_rectangle;
  // Shape globals the head reads (canonical.hpp): 0 (first model),
  // kExtentGlobals (extents and centroid height) or kShapeGlobals (all).
  int globals = kShapeGlobals;
  // Heights from the floor the object stands on when the caller knows it
  // (CanonicalConfig::floor); trained with the floor withheld from some
  // samples, so an unknown floor falls back to the lowest point.
  bool floor = true;
};

struct DescriptorNetImpl : torch::nn::Module {
  explicit DescriptorNetImpl(const NetConfig& config);
  // x: [batch, points, in], g: [batch, globals] (ignored when globals == 0)
  // -> [batch, out], unit rows.
  torch::Tensor forward(const torch::Tensor& x, const torch::Tensor& g);
  NetConfig config;
  torch::nn::Linear l1{nullptr}, l2{nullptr}, l3{nullptr}, h1{nullptr}, h2{nullptr};
};
TORCH_MODULE(DescriptorNet);

// The preprocessing a network was trained with.
CanonicalConfig canonical_config(const NetConfig& config, uint64_t seed = CanonicalConfig{}.seed);

// Packs clouds[begin, end) (made with canonical_config) into the network's
// inputs and runs it: [end - begin, out]. Gradients flow unless the caller
// holds a NoGradGuard.
torch::Tensor describe_clouds(DescriptorNet& net, const std::vector<CanonicalCloud>& clouds, size_t begin, size_t end);

// Rows [n * samples, out] holding `samples` consecutive rows per object ->
// [n, out]: each object's mean, L2-normalised (contiguous).
torch::Tensor mean_of_samples(const torch::Tensor& rows, int samples);

// Writes the weights file and its .sha256 sidecar (temp name, then rename).
void save_weights(DescriptorNet& net, const std::string& path);
// Verifies the checksum and layout; throws lista::Error with a one-line
// reason (missing file, missing/mismatching checksum, bad layout). The
// verified SHA-256 (hex) goes to `sha256` when given.
DescriptorNet load_weights(const std::string& path, std::string* sha256 = nullptr);

}  // namespace lista::objfeat
