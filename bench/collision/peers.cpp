#include "peers.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <embree3/rtcore.h>
#include <fcl/fcl.h>

namespace cathbox::collision::bench {

namespace {

struct V3 {
  float x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 mad(V3 a, V3 d, float t) { return {a.x + t * d.x, a.y + t * d.y, a.z + t * d.z}; }

// Closest point on triangle abc to p by Voronoi regions, in float: what an Embree user writes.
V3 closest_on_triangle(V3 p, V3 a, V3 b, V3 c) {
  const V3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const V3 bp = sub(p, b);
  const float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return mad(a, ab, d1 / (d1 - d3));
  const V3 cp = sub(p, c);
  const float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return mad(a, ac, d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
    return mad(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denom = 1.0f / (va + vb + vc);
  return mad(mad(a, ab, vb * denom), ac, vc * denom);
}

class EmbreeIndex final : public PeerIndex {
 public:
  explicit EmbreeIndex(const vessel::SurfaceMesh& mesh) : mesh_(mesh) {
    device_ = rtcNewDevice(nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.vertex_count()));
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
      v[3 * i] = mesh.positions_mm[i].x;
      v[3 * i + 1] = mesh.positions_mm[i].y;
      v[3 * i + 2] = mesh.positions_mm[i].z;
    }
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh.triangle_count()));
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) t[i] = mesh.triangles[i];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
  }
  ~EmbreeIndex() override {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeIndex(const EmbreeIndex&) = delete;
  EmbreeIndex& operator=(const EmbreeIndex&) = delete;

  double distance(const glm::dvec3& p) override {
    RTCPointQuery query;
    query.x = static_cast<float>(p.x);
    query.y = static_cast<float>(p.y);
    query.z = static_cast<float>(p.z);
    query.time = 0.0f;
    query.radius = std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    Result result{this, std::numeric_limits<float>::infinity()};
    rtcPointQuery(scene_, &query, &context, &EmbreeIndex::callback, &result);
    return result.distance;
  }

 private:
  struct Result {
    EmbreeIndex* self;
    float distance;
  };

  static bool callback(RTCPointQueryFunctionArguments* args) {
    auto* result = static_cast<Result*>(args->userPtr);
    const vessel::SurfaceMesh& m = result->self->mesh_;
    const std::size_t f = args->primID;
    auto vertex = [&](int k) {
      const glm::vec3& q = m.positions_mm[m.triangles[3 * f + static_cast<std::size_t>(k)]];
      return V3{q.x, q.y, q.z};
    };
    const V3 p{args->query->x, args->query->y, args->query->z};
    const V3 d = sub(p, closest_on_triangle(p, vertex(0), vertex(1), vertex(2)));
    const float dist = std::sqrt(dot(d, d));
    if (dist < args->query->radius) {
      args->query->radius = dist;
      result->distance = dist;
      return true;
    }
    return false;
  }

  const vessel::SurfaceMesh& mesh_;
  RTCDevice device_;
  RTCScene scene_;
};

class FclIndex final : public PeerIndex {
 public:
  explicit FclIndex(const vessel::SurfaceMesh& mesh) {
    std::vector<fcl::Vector3d> vertices;
    vertices.reserve(mesh.vertex_count());
    for (const glm::vec3& q : mesh.positions_mm) vertices.emplace_back(q.x, q.y, q.z);
    std::vector<fcl::Triangle> triangles;
    triangles.reserve(mesh.triangle_count());
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
      triangles.emplace_back(mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]);
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    model->beginModel();
    model->addSubModel(vertices, triangles);
    model->endModel();
    mesh_object_ = std::make_unique<fcl::CollisionObjectd>(model);
    point_object_ = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Sphered>(kRadius));
    request_.enable_nearest_points = true;
  }

  double distance(const glm::dvec3& p) override {
    point_object_->setTranslation(fcl::Vector3d(p.x, p.y, p.z));
    point_object_->computeAABB();
    fcl::DistanceResultd result;
    fcl::distance(point_object_.get(), mesh_object_.get(), request_, result);
    return result.min_distance + kRadius;
  }

 private:
  static constexpr double kRadius = 1e-6;
  std::unique_ptr<fcl::CollisionObjectd> mesh_object_;
  std::unique_ptr<fcl::CollisionObjectd> point_object_;
  fcl::DistanceRequestd request_;
};

}  // namespace

std::unique_ptr<PeerIndex> make_embree(const vessel::SurfaceMesh& mesh) { return std::make_unique<EmbreeIndex>(mesh); }
std::unique_ptr<PeerIndex> make_fcl(const vessel::SurfaceMesh& mesh) { return std::make_unique<FclIndex>(mesh); }

}  // namespace cathbox::collision::bench
