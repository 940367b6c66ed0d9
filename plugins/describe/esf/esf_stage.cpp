// describe.esf: PCL's Ensemble of Shape Functions (Wohlkinger & Vincze 2011),
// a global 640-bin descriptor (distance, angle, area and distance-ratio
// histograms of random point triples, split by in/out/mixed voxel
// occupancy). Already one vector per object; rows are L2-normalised.
#include <lista/plugin.hpp>
#include <lista_pcl/convert.hpp>

#include <pcl/features/esf.h>

#include <cstdlib>
#include <ctime>
#include <mutex>

// PCL's ESF seeds rand() from the wall clock on every call, which would make
// runs differ. Its template is compiled here with that clock read replaced by
// a constant so the same object always gives the same descriptor.
namespace lista::describe {
inline std::time_t fixed_clock(std::time_t*) { return std::time_t(0x5eed); }
}  // namespace lista::describe
#define time(x) lista::describe::fixed_clock(x)
#include <pcl/features/impl/esf.hpp>
#undef time

namespace lista::describe {
namespace {

// rand() is process-global: serialise ESF computations.
std::mutex esf_mutex;

class EsfStage : public Stage {
 public:
  explicit EsfStage(const Params&) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "describe.esf";
    i.version = "1.0.0";
    i.summary = "Ensemble of Shape Functions (PCL), one 640-d row per object";
    i.doc =
        "PCL's Ensemble of Shape Functions on all of an object's points: one rotation-invariant 640-d row per "
        "object, L2-normalised; deterministic, no parameters. "
        "Details: docs/descriptors.md, \"describe.esf\".";
    i.inputs = {{"objects", "objects", "objects to describe"}};
    i.outputs = {{"descriptors", "descriptors", "one unit-norm 640-d row per object"}};
    return i;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const ObjectSet& objects = in.get<ObjectSet>("objects");
    DescriptorSet out;
    out.method = "describe.esf";
    out.normalized = true;
    out.values = DescriptorSet::Matrix::Zero(long(objects.objects.size()), 640);
    std::lock_guard<std::mutex> lock(esf_mutex);
    for (size_t i = 0; i < objects.objects.size(); ++i) {
      ctx.throw_if_cancelled();
      const Object& o = objects.objects[i];
      if (o.points.empty()) throw Error("object " + std::to_string(o.id) + " has no points to describe");
      pcl::ESFEstimation<pcl::PointXYZ, pcl::ESFSignature640> est;
      est.setInputCloud(pcl_convert::to_xyz(o.points));
      pcl::PointCloud<pcl::ESFSignature640> sig;
      est.compute(sig);
      Eigen::RowVectorXf row = Eigen::RowVectorXf::Ones(640);
      if (sig.size() == 1) row = Eigen::Map<const Eigen::RowVectorXf>(sig[0].histogram, 640);
      if (!row.allFinite() || !(row.norm() > 0.f)) row.setOnes();  // degenerate object
      out.values.row(long(i)) = row / row.norm();
      out.object_ids.push_back(o.id);
    }
    return Outputs::of("descriptors", std::move(out));
  }
};

}  // namespace
}  // namespace lista::describe

LISTA_STAGE_PLUGIN(lista::describe::EsfStage::info, lista::describe::EsfStage)
