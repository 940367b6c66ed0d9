// Descriptor training/evaluation data: partial scans ("views") of object
// instances, each tagged with its shape. Read from a `lista-sim views` folder
// (docs/datasets.md) or generated in code. Geometric identity is the shape:
// two instances of one mesh are indistinguishable to a geometry descriptor,
// so views are labelled and split by shape.
#pragma once

#include <lista/points.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace lista::objfeat {

struct View {
  int label = 0;    // identity for metric learning and retrieval (the shape)
  int variant = 0;  // the generator's own shape before look-alikes were merged
                    // (index.json "variant"; equals the shape where absent)
  int instance = 0; // object instance in the data set
  int split = -1;   // -1: unassigned, 0: training, 1: held out (given by the data set)
  int source = 0;   // index into ViewSet::sources: where the shape came from
  // How the view was taken and what it shows part of (index.json; for
  // benchmark breakdowns, never for a descriptor): the sensor's name ("" if
  // not given), its distance to the object (m) and the whole shape's size
  // (shapes[].extent: x, y along the shape's own axes, height; m); NaN where
  // not given.
  std::string sensor;
  float distance = std::numeric_limits<float>::quiet_NaN();
  std::array<float, 3> extent{std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::quiet_NaN()};
  PointSet points;  // object frame
};

struct ViewSet {
  std::vector<View> views;
  // Shape sources (index.json shapes[].source, e.g. "procedural",
  // "sweethome3d"; "unknown" where a shape has none), numbered in order of
  // first appearance.
  std::vector<std::string> sources;
};

// index.json ("lista-views/1") and its PCD files; splits 'val' and 'test'
// are held out. Throws lista::Error naming the file for anything malformed.
// Which point channels a read keeps: everything but the ground-truth labels
// (descriptors must not see them), or the coordinates alone (what training
// reads; the 24 bytes per point of xyz, intensity, scan and index drop to 12,
// which decides how many views fit in memory).
enum class ViewChannels { all, xyz_only };
ViewSet read_views(const std::string& folder, ViewChannels channels = ViewChannels::all);
// Several folders as one set: a shape id has one label across all of them
// (e.g. single-sweep and multi-sweep views of the same objects).
ViewSet read_views(const std::vector<std::string>& folders, ViewChannels channels = ViewChannels::all);

// `shapes` synthetic shapes (synthetic.hpp), one instance each,
// `per_instance` partial views each, no intensity. Deterministic from seed.
ViewSet synthetic_views(int shapes, int per_instance, uint64_t seed);

// The data set's own split where views carry one, else a seeded `holdout`
// fraction of labels goes to `test`.
void split_by_shape(const ViewSet& all, double holdout, uint64_t seed, ViewSet& train, ViewSet& test);

}  // namespace lista::objfeat
