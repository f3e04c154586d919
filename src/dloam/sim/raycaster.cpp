// Embree scenes: static scene (robust, high quality, built once), one scene per actor mesh
// (built once), and a dynamic top-level scene of instances rebuilt once per sweep.
#include "dloam/sim/raycaster.hpp"

#include <embree3/rtcore.h>

#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace dloam::sim {

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCScene> children;      // [0] static, [1 + i] actor i
  std::vector<RTCGeometry> instances;  // same indexing; top-level geomID == index
  std::vector<bool> enabled;

  void check(const char* what) const {
    const RTCError err = rtcGetDeviceError(device);
    if (err != RTC_ERROR_NONE)
      throw std::runtime_error(std::string("embree: ") + what + " failed (error " +
                               std::to_string(static_cast<int>(err)) + ")");
  }

  RTCScene make_mesh_scene(const Mesh& mesh, bool robust) {
    RTCScene scene = rtcNewScene(device);
    if (robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    if (!mesh.empty()) {
      RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
          geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
      auto* t = static_cast<std::uint32_t*>(
          rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t),
                                  mesh.triangles.size()));
      check("allocating mesh buffers");
      for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        std::memcpy(v + 3 * i, mesh.vertices[i].data(), 3 * sizeof(float));
      for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        std::memcpy(t + 3 * i, mesh.triangles[i].data(), 3 * sizeof(std::uint32_t));
      rtcCommitGeometry(geom);
      rtcAttachGeometry(scene, geom);
      rtcReleaseGeometry(geom);
    }
    rtcCommitScene(scene);
    check("building a mesh scene");
    return scene;
  }

  RTCGeometry make_instance(RTCScene child, unsigned steps) {
    RTCGeometry inst = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, child);
    rtcSetGeometryTimeStepCount(inst, steps);
    const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    for (unsigned k = 0; k < steps; ++k)
      rtcSetGeometryTransform(inst, k, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
    rtcCommitGeometry(inst);
    rtcAttachGeometry(top, inst);
    return inst;
  }
};

RayCaster::RayCaster(const Mesh& static_mesh, const std::vector<const Mesh*>& actor_meshes)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.device = rtcNewDevice(nullptr);
  if (m.device == nullptr) throw std::runtime_error("embree: cannot create a device");
  m.top = rtcNewScene(m.device);
  rtcSetSceneFlags(m.top, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(m.top, RTC_BUILD_QUALITY_LOW);
  m.children.push_back(m.make_mesh_scene(static_mesh, true));
  m.instances.push_back(m.make_instance(m.children.back(), 1));
  for (const Mesh* mesh : actor_meshes) {
    m.children.push_back(m.make_mesh_scene(*mesh, false));
    m.instances.push_back(m.make_instance(m.children.back(), kMotionSteps));
    rtcDisableGeometry(m.instances.back());
  }
  m.enabled.assign(m.instances.size(), false);
  m.enabled[0] = true;
  commit();
}

RayCaster::~RayCaster() {
  Impl& m = *impl_;
  for (RTCGeometry g : m.instances) rtcReleaseGeometry(g);
  if (m.top != nullptr) rtcReleaseScene(m.top);
  for (RTCScene s : m.children) rtcReleaseScene(s);
  if (m.device != nullptr) rtcReleaseDevice(m.device);
}

void RayCaster::set_actor_motion(std::size_t actor, const std::vector<Pose>& poses) {
  if (poses.size() != static_cast<std::size_t>(kMotionSteps))
    throw std::invalid_argument("raycaster: need " + std::to_string(kMotionSteps) + " poses per actor");
  Impl& m = *impl_;
  RTCGeometry inst = m.instances.at(actor + 1);
  for (unsigned k = 0; k < static_cast<unsigned>(kMotionSteps); ++k) {
    const Eigen::Matrix<float, 3, 4> xfm =
        poses[k].matrix().topRows<3>().cast<float>();  // column-major storage
    rtcSetGeometryTransform(inst, k, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm.data());
  }
  rtcCommitGeometry(inst);
  if (!m.enabled[actor + 1]) rtcEnableGeometry(inst);
  m.enabled[actor + 1] = true;
}

void RayCaster::disable_actor(std::size_t actor) {
  Impl& m = *impl_;
  if (m.enabled.at(actor + 1)) rtcDisableGeometry(m.instances[actor + 1]);
  m.enabled[actor + 1] = false;
}

void RayCaster::commit() {
  rtcCommitScene(impl_->top);
  impl_->check("building the top-level scene");
}

RayCaster::Hit RayCaster::cast(const Vec3& origin, const Vec3& direction, float tau, float tnear,
                               float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(origin.x());
  rh.ray.org_y = static_cast<float>(origin.y());
  rh.ray.org_z = static_cast<float>(origin.z());
  rh.ray.dir_x = static_cast<float>(direction.x());
  rh.ray.dir_y = static_cast<float>(direction.y());
  rh.ray.dir_z = static_cast<float>(direction.z());
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.time = tau;
  rh.ray.mask = std::numeric_limits<unsigned>::max();
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->top, &context, &rh);
  Hit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.range = rh.ray.tfar;
  hit.actor = static_cast<int>(rh.hit.instID[0]) - 1;
  hit.primitive = rh.hit.primID;
  hit.normal = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  return hit;
}

void RayCaster::cast_packet(const Vec3* origins, const Vec3* directions, int count, float tau, float tnear,
                            float tfar, Hit* hits) const {
  if (count < 0 || count > kPacket)
    throw std::invalid_argument("raycaster: packet of " + std::to_string(count) + " rays");
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 rh{};
  alignas(64) int valid[kPacket];
  for (int i = 0; i < kPacket; ++i) {
    valid[i] = i < count ? -1 : 0;
    const Vec3 d = i < count ? directions[i] : Vec3::UnitX();
    const Vec3 o = i < count ? origins[i] : origins[0];
    rh.ray.org_x[i] = static_cast<float>(o.x());
    rh.ray.org_y[i] = static_cast<float>(o.y());
    rh.ray.org_z[i] = static_cast<float>(o.z());
    rh.ray.dir_x[i] = static_cast<float>(d.x());
    rh.ray.dir_y[i] = static_cast<float>(d.y());
    rh.ray.dir_z[i] = static_cast<float>(d.z());
    rh.ray.tnear[i] = tnear;
    rh.ray.tfar[i] = tfar;
    rh.ray.time[i] = tau;
    rh.ray.mask[i] = std::numeric_limits<unsigned>::max();
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect16(valid, impl_->top, &context, &rh);
  for (int i = 0; i < count; ++i) {
    Hit& hit = hits[i];
    hit = Hit{};
    if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    hit.range = rh.ray.tfar[i];
    hit.actor = static_cast<int>(rh.hit.instID[0][i]) - 1;
    hit.primitive = rh.hit.primID[i];
    hit.normal = Eigen::Vector3f(rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]);
  }
}

}  // namespace dloam::sim
