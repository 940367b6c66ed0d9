#include "raycaster.hpp"

#include <lista/error.hpp>

#include <embree3/rtcore.h>

#include <cstring>
#include <limits>

namespace lista::sim {
namespace {

// One Embree device for the whole process (creating one is expensive).
RTCDevice device() {
  static RTCDevice dev = [] {
    RTCDevice d = rtcNewDevice("threads=1");  // we parallelise over rays ourselves
    if (!d) throw Error("lista-sim: cannot create an Embree device");
    return d;
  }();
  return dev;
}

}  // namespace

struct RayScene::Impl {
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }
};

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {}
RayScene::~RayScene() = default;

void RayScene::add(const TriMesh& mesh, const Eigen::Isometry3f& pose, uint32_t label, float reflectivity) {
  const int base = int(vertices_.size());
  for (const auto& v : mesh.vertices) vertices_.push_back(pose * v);
  for (const auto& t : mesh.triangles) {
    triangles_.push_back(t + Eigen::Vector3i::Constant(base));
    labels_.push_back(label);
    reflectivity_.push_back(reflectivity);
  }
}

void RayScene::commit() {
  if (impl_->scene) throw Error("lista-sim: RayScene committed twice");
  impl_->scene = rtcNewScene(device());
  if (triangles_.empty()) {
    rtcCommitScene(impl_->scene);
    return;
  }
  RTCGeometry geom = rtcNewGeometry(device(), RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree copies into its own (padded) buffers.
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), vertices_.size()));
  std::memcpy(vb, vertices_.data(), vertices_.size() * 3 * sizeof(float));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), triangles_.size()));
  std::memcpy(ib, triangles_.data(), triangles_.size() * 3 * sizeof(unsigned));
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcCommitScene(impl_->scene);
  vertices_.clear();
  vertices_.shrink_to_fit();
  triangles_.clear();
  triangles_.shrink_to_fit();
}

Hit RayScene::intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tmin, float tmax) const {
  Hit hit;
  if (!impl_->scene || labels_.empty()) return hit;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = tmin;
  rh.ray.tfar = tmax;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;  // Embree skips rays whose mask matches nothing
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.t = rh.ray.tfar;
  hit.label = labels_[rh.hit.primID];
  hit.reflectivity = reflectivity_[rh.hit.primID];
  hit.normal = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  return hit;
}

}  // namespace lista::sim
