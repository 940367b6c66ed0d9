// example.extent: a minimal third-party descriptor plugin (docs/plugin-sdk.md).
//
// One 6-d row per object, built from the object's shape proportions only:
//   [major extent, minor extent, w * height, major spread, minor spread, w * vertical spread]
// "major/minor" are the principal axes of the points' horizontal (x, y)
// covariance, so the row does not change when the object turns about z (yaw)
// or moves. Extents are trimmed ranges of the points projected on each axis,
// spreads their standard deviations, w = height_weight. Rows are L2-normalised,
// so the row describes proportions, not absolute size.
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <vector>

namespace example_extent {
namespace {

using namespace lista;

constexpr int kDim = 6;

// Range of `values` without the `trim` fraction at each end (nearest rank;
// symmetric, so negating every value gives the same range).
double trimmed_range(std::vector<double>& values, double trim) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  const size_t cut = static_cast<size_t>(std::floor(trim * double(n - 1)));
  return values[n - 1 - cut] - values[cut];
}

double standard_deviation(const std::vector<double>& values) {
  double mean = 0.0, square = 0.0;
  for (double v : values) mean += v;
  mean /= double(values.size());
  for (double v : values) square += (v - mean) * (v - mean);
  return std::sqrt(square / double(values.size()));
}

// The stage's settings; each is declared once, bound to its field, in
// param_table() (its default is the field's).
struct ExtentConfig {
  double height_weight = 1.0;
  double trim = 0.02;
};

const ParamTable<ExtentConfig>& param_table() {
  return ParamTable<ExtentConfig>::once([](ParamTable<ExtentConfig>& t) {
    t.bind("height_weight", &ExtentConfig::height_weight, "weight of the vertical features against the horizontal ones")
        .range(0.0, 10.0);
    t.bind("trim", &ExtentConfig::trim, "fraction of points ignored at each end of an axis when measuring extents")
        .range(0.0, 0.25);
  });
}

class ExtentStage : public Stage {
 public:
  // Parameters arrive validated (type and range checked by the core against
  // the declarations), so the constructor only reads them.
  explicit ExtentStage(const Params& p) : config_(param_table().read(p)) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "example.extent";
    i.version = "1.0.0";
    i.summary = "example descriptor: yaw-invariant extents and spreads, one 6-d row per object";
    i.doc =
        "Yaw- and translation-invariant proportions of each object: extents and spreads along its horizontal "
        "principal axes and z, one L2-normalised 6-d row. The worked example of the plugin SDK. "
        "Details: docs/plugin-sdk.md, \"What the example computes\".";
    // The same port names and types as every describe.* plugin, so it drops
    // into a pipeline in place of any of them.
    i.inputs = {{"objects", "objects", "objects to describe"}};
    i.outputs = {{"descriptors", "descriptors", "one unit-norm 6-d row per object"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const ObjectSet& objects = in.get<ObjectSet>("objects");
    DescriptorSet out;
    out.method = "example.extent";
    out.normalized = true;
    out.values = DescriptorSet::Matrix::Zero(long(objects.objects.size()), kDim);
    for (size_t i = 0; i < objects.objects.size(); ++i) {
      ctx.throw_if_cancelled();
      const Object& o = objects.objects[i];
      if (o.points.empty()) throw Error("object " + std::to_string(o.id) + " has no points to describe");
      out.values.row(long(i)) = describe(o.points);
      out.object_ids.push_back(o.id);
    }
    ctx.record("objects", double(objects.objects.size()));
    return Outputs::of("descriptors", std::move(out));
  }

 private:
  Eigen::Matrix<float, 1, kDim> describe(const PointSet& points) const {
    const size_t n = points.size();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : points.xyz) mean += p.cast<double>();
    mean /= double(n);
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : points.xyz) {
      const Eigen::Vector2d d = p.cast<double>().head<2>() - mean.head<2>();
      cov += d * d.transpose();
    }
    // Eigenvectors in increasing eigenvalue order: column 1 is the major axis.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(cov / double(n));
    const Eigen::Vector2d major = solver.eigenvectors().col(1), minor = solver.eigenvectors().col(0);

    std::vector<double> a(n), b(n), z(n);
    for (size_t k = 0; k < n; ++k) {
      const Eigen::Vector3d d = points.xyz[k].cast<double>() - mean;
      a[k] = major.dot(d.head<2>());
      b[k] = minor.dot(d.head<2>());
      z[k] = d.z();
    }
    const double spread_a = standard_deviation(a), spread_b = standard_deviation(b), spread_z = standard_deviation(z);
    // Sorted, so a near-circular footprint (eigenvectors ill-defined) still
    // gives major >= minor whichever axes the solver returned.
    double extent_a = trimmed_range(a, config_.trim), extent_b = trimmed_range(b, config_.trim);
    if (extent_b > extent_a) std::swap(extent_a, extent_b);
    const double height = trimmed_range(z, config_.trim);

    Eigen::Matrix<double, 1, kDim> row;
    row << extent_a, extent_b, config_.height_weight * height, std::max(spread_a, spread_b),
        std::min(spread_a, spread_b), config_.height_weight * spread_z;
    const double norm = row.norm();
    // All points at one spot (or height_weight 0 on a single point): no shape
    // to describe; every such object gets the same uniform row.
    if (!(norm > 1e-12)) return Eigen::Matrix<float, 1, kDim>::Constant(float(1.0 / std::sqrt(double(kDim))));
    return (row / norm).cast<float>();
  }

  ExtentConfig config_;
};

}  // namespace
}  // namespace example_extent

LISTA_STAGE_PLUGIN(example_extent::ExtentStage::info, example_extent::ExtentStage)
