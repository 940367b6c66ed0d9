// describe.rift: PCL's RIFT (Lazebnik et al. 2005) — histograms of intensity
// gradient orientation against the radial direction, over distance rings —
// on a voxel-downsampled object, with gradients from PCL's
// IntensityGradientEstimation. Reduced to one row per object by mean
// pooling the keypoints' 32-bin histograms (4 rings x 8 orientations), L2-normalised.
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>
#include <lista_pcl/convert.hpp>

#include <pcl/features/intensity_gradient.h>
#include <pcl/features/normal_3d.h>
#include <pcl/features/rift.h>
#include <pcl/features/impl/rift.hpp>  // Histogram<32> is not among PCL's precompiled types
#include <pcl/filters/voxel_grid.h>
#include <pcl/search/kdtree.h>

#include <algorithm>

namespace lista::describe {
namespace {

constexpr int kRings = 4, kOrientations = 8, kBins = kRings * kOrientations;
using RiftHistogram = pcl::Histogram<kBins>;

struct RiftConfig {
  double voxel = 0.03;          // m
  double normal_radius = 0.08;  // m
  double support_radius = 0.2;  // m
};

const ParamTable<RiftConfig>& param_table() {
  using C = RiftConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("voxel", &C::voxel, "downsampling voxel edge (keypoint spacing)").range(0.001, 1.0).unit("m");
    t.bind("normal_radius", &C::normal_radius, "normal and gradient estimation radius").range(0.005, 2.0).unit("m");
    t.bind("support_radius", &C::support_radius, "RIFT support radius").range(0.01, 5.0).unit("m");
  });
}

class RiftStage : public Stage {
 public:
  explicit RiftStage(const Params& p) : c_(param_table().read(p)) {
    if (c_.support_radius <= c_.voxel) throw Error("support_radius must be larger than voxel");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "describe.rift";
    i.version = "1.0.0";
    i.summary = "RIFT intensity-gradient histograms (PCL) mean-pooled into one 32-d row per object";
    i.doc =
        "RIFT intensity-gradient histograms (PCL; 4 rings x 8 orientations) at voxel-downsampled points, mean-pooled into one L2-normalised 32-d row per object; intensity is rescaled per object, and height "
        "stands in where there is none. "
        "Details: docs/descriptors.md, \"describe.rift\".";
    i.inputs = {{"objects", "objects", "objects to describe"}};
    i.outputs = {{"descriptors", "descriptors", "one unit-norm 32-d row per object"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const ObjectSet& objects = in.get<ObjectSet>("objects");
    const long n = long(objects.objects.size());
    DescriptorSet out;
    out.method = "describe.rift";
    out.normalized = true;
    out.values = DescriptorSet::Matrix::Zero(n, kBins);
    int without_intensity = 0;
    for (const Object& o : objects.objects) {
      if (o.points.empty()) throw Error("object " + std::to_string(o.id) + " has no points to describe");
      without_intensity += !o.points.has_intensity();
      out.object_ids.push_back(o.id);
    }
    if (without_intensity > 0)
      ctx.warn(std::to_string(without_intensity) + " objects have no intensity; RIFT uses their height instead");
    // Objects are independent: one per thread, each with its own estimators.
#pragma omp parallel for schedule(dynamic) num_threads(ctx.threads())
    for (long i = 0; i < n; ++i) out.values.row(i) = describe(objects.objects[size_t(i)].points);
    return Outputs::of("descriptors", std::move(out));
  }

 private:
  Eigen::RowVectorXf describe(const PointSet& points) const {
    auto cloud = pcl_convert::to_xyzi(points);
    if (!points.has_intensity()) {
      float zmin = points.xyz.front().z();
      for (const auto& p : points.xyz) zmin = std::min(zmin, p.z());
      for (auto& p : *cloud) p.intensity = p.z - zmin;
    }
    float lo = 1e30f, hi = -1e30f;
    for (const auto& p : *cloud) { lo = std::min(lo, p.intensity); hi = std::max(hi, p.intensity); }
    const float scale = hi > lo ? 1.f / (hi - lo) : 0.f;
    for (auto& p : *cloud) p.intensity = (p.intensity - lo) * scale;

    pcl::PointCloud<pcl::PointXYZI>::Ptr keys(new pcl::PointCloud<pcl::PointXYZI>);
    pcl::VoxelGrid<pcl::PointXYZI> grid;
    grid.setInputCloud(cloud);
    grid.setLeafSize(float(c_.voxel), float(c_.voxel), float(c_.voxel));
    grid.filter(*keys);

    auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZI>>();
    pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
    pcl::NormalEstimation<pcl::PointXYZI, pcl::Normal> ne;
    ne.setInputCloud(keys);
    ne.setSearchMethod(tree);
    ne.setRadiusSearch(c_.normal_radius);
    ne.compute(*normals);

    pcl::PointCloud<pcl::IntensityGradient>::Ptr gradients(new pcl::PointCloud<pcl::IntensityGradient>);
    pcl::IntensityGradientEstimation<pcl::PointXYZI, pcl::Normal, pcl::IntensityGradient> ge;
    ge.setInputCloud(keys);
    ge.setInputNormals(normals);
    ge.setSearchMethod(tree);
    ge.setRadiusSearch(c_.normal_radius);
    ge.compute(*gradients);
    for (auto& g : *gradients)  // flat or isolated points give NaN gradients
      if (!std::isfinite(g.gradient_x) || !std::isfinite(g.gradient_y) || !std::isfinite(g.gradient_z))
        g.gradient_x = g.gradient_y = g.gradient_z = 0.f;

    pcl::PointCloud<RiftHistogram> rift;
    pcl::RIFTEstimation<pcl::PointXYZI, pcl::IntensityGradient, RiftHistogram> re;
    re.setInputCloud(keys);
    re.setInputGradient(gradients);
    re.setSearchMethod(tree);
    re.setRadiusSearch(c_.support_radius);
    re.setNrDistanceBins(kRings);
    re.setNrGradientBins(kOrientations);
    re.compute(rift);

    Eigen::RowVectorXf sum = Eigen::RowVectorXf::Zero(kBins);
    for (const auto& h : rift) {
      Eigen::Map<const Eigen::RowVectorXf> v(h.histogram, kBins);
      if (v.allFinite()) sum += v;
    }
    if (!(sum.norm() > 0.f)) sum.setConstant(1.f);  // degenerate object: a fixed, valid row
    return sum / sum.norm();
  }

  const RiftConfig c_;
};

}  // namespace
}  // namespace lista::describe

LISTA_STAGE_PLUGIN(lista::describe::RiftStage::info, lista::describe::RiftStage)
