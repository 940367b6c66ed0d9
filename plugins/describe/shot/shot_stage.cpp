// describe.shot: PCL's SHOT (Tombari et al. 2010, SHOTEstimationOMP) on a
// voxel-downsampled object, reduced to one row per object by mean pooling:
// the average of the keypoints' 352-bin histograms, L2-normalised. Mean
// pooling is order- and count-invariant and keeps SHOT's rotation
// invariance; it needs no codebook, so it works on any object set.
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>
#include <lista_pcl/convert.hpp>
#include <lista_pcl/fast_kdtree.hpp>

#include <lista_pcl/quiet.hpp>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/features/shot_omp.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/search/kdtree.h>

#include <cmath>

namespace lista::describe {
namespace {

struct ShotConfig {
  double voxel = 0.03;          // m
  double normal_radius = 0.08;  // m
  double support_radius = 0.2;  // m
};

const ParamTable<ShotConfig>& param_table() {
  using C = ShotConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("voxel", &C::voxel, "downsampling voxel edge (keypoint spacing)").range(0.001, 1.0).unit("m");
    t.bind("normal_radius", &C::normal_radius, "normal estimation radius").range(0.005, 2.0).unit("m");
    t.bind("support_radius", &C::support_radius, "SHOT support radius").range(0.01, 5.0).unit("m");
  });
}

class ShotStage : public Stage {
 public:
  explicit ShotStage(const Params& p) : c_(param_table().read(p)) {
    if (c_.support_radius <= c_.voxel) throw Error("support_radius must be larger than voxel");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "describe.shot";
    i.version = "1.0.0";
    i.summary = "SHOT histograms (PCL, OpenMP) mean-pooled into one 352-d row per object";
    i.doc =
        "SHOT histograms (PCL) at voxel-downsampled points, mean-pooled into one rotation-invariant, L2-normalised "
        "352-d row per object. Slow on large objects. "
        "Details: docs/descriptors.md, \"describe.shot\".";
    i.inputs = {{"objects", "objects", "objects to describe"}};
    i.outputs = {{"descriptors", "descriptors", "one unit-norm 352-d row per object"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const ObjectSet& objects = in.get<ObjectSet>("objects");
    DescriptorSet out;
    out.method = "describe.shot";
    out.normalized = true;
    out.values = DescriptorSet::Matrix::Zero(long(objects.objects.size()), 352);
    for (size_t i = 0; i < objects.objects.size(); ++i) {
      ctx.throw_if_cancelled();
      const Object& o = objects.objects[i];
      if (o.points.empty()) throw Error("object " + std::to_string(o.id) + " has no points to describe");
      out.values.row(long(i)) = describe(o.points, ctx.threads());
      out.object_ids.push_back(o.id);
    }
    return Outputs::of("descriptors", std::move(out));
  }

 private:
  Eigen::RowVectorXf describe(const PointSet& points, int threads) const {
    auto cloud = pcl_convert::to_xyz(points);
    pcl::PointCloud<pcl::PointXYZ>::Ptr keys(new pcl::PointCloud<pcl::PointXYZ>);
    pcl::VoxelGrid<pcl::PointXYZ> grid;
    grid.setInputCloud(cloud);
    grid.setLeafSize(float(c_.voxel), float(c_.voxel), float(c_.voxel));
    grid.filter(*keys);

    auto tree = std::make_shared<pcl_search::FastKdTree>();
    pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
    pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne(threads);
    ne.setInputCloud(keys);
    ne.setSearchMethod(tree);
    ne.setRadiusSearch(c_.normal_radius);
    ne.compute(*normals);

    pcl::PointCloud<pcl::SHOT352> shots;
    pcl::SHOTEstimationOMP<pcl::PointXYZ, pcl::Normal, pcl::SHOT352> se(static_cast<unsigned>(threads));
    se.setInputCloud(keys);
    se.setInputNormals(normals);
    se.setSearchMethod(tree);
    se.setRadiusSearch(c_.support_radius);
    {
      // SHOT prints a warning per keypoint with NaN normals or no valid frame,
      // routine on sparse partial scans (100k lines per benchmark run). Those
      // keypoints are dropped below anyway: keep PCL quiet meanwhile.
      pcl_convert::QuietPcl quiet;
      se.compute(shots);
    }

    Eigen::RowVectorXf sum = Eigen::RowVectorXf::Zero(352);
    int valid = 0;
    for (const auto& s : shots) {
      Eigen::Map<const Eigen::RowVectorXf> h(s.descriptor, 352);
      if (!h.allFinite() || h.isZero()) continue;  // too few neighbours or no normal
      sum += h;
      ++valid;
    }
    if (valid == 0) sum.setConstant(1.f);  // degenerate object: a fixed, valid row
    return sum / sum.norm();
  }

  const ShotConfig c_;
};

}  // namespace
}  // namespace lista::describe

LISTA_STAGE_PLUGIN(lista::describe::ShotStage::info, lista::describe::ShotStage)
