// The scene in Embree: every primitive of every instance flattened to a world-space triangle
// mesh (no Embree instancing: the shading attributes are needed in world space anyway).
#include "internal.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace speculum::reference {
namespace {

Geometry flatten(const Primitive& p, const glm::mat4& world) {
    Geometry g;
    g.material = p.material;
    glm::mat3 m(world);
    // The cofactor matrix is the inverse transpose up to a positive scale once its sign is
    // fixed by the determinant: the vertex shader's normal transform (gbuffer.vert).
    glm::mat3 cof(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
    float det = glm::dot(m[0], cof[0]);
    float sign = det < 0.0f ? -1.0f : 1.0f;
    g.positions.reserve(p.vertices.size());
    for (const Vertex& v : p.vertices) {
        g.positions.push_back(glm::vec3(world * glm::vec4(v.position, 1.0f)));
        g.normals.push_back(cof * v.normal * sign);
        g.tangents.push_back(glm::vec4(m * glm::vec3(v.tangent), v.tangent.w));
        g.uvs.push_back(v.uv);
    }
    g.indices = p.indices;
    g.indices.resize(g.indices.size() / 3 * 3);
    // A mirroring transform turns counter-clockwise into clockwise: swap two corners so that the
    // winding still names glTF's front face.
    if (det < 0.0f)
        for (size_t i = 0; i + 2 < g.indices.size(); i += 3) std::swap(g.indices[i + 1], g.indices[i + 2]);
    return g;
}

void attach(RTCDevice device, RTCScene scene, const Geometry& g, uint32_t id) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), g.positions.size()));
    for (size_t i = 0; i < g.positions.size(); ++i)
        for (int c = 0; c < 3; ++c) vb[i * 3 + size_t(c)] = g.positions[i][c];
    auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(uint32_t), g.indices.size() / 3));
    std::copy(g.indices.begin(), g.indices.end(), ib);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene, geom, id);
    rtcReleaseGeometry(geom);
}

RTCRayHit makeRay(glm::vec3 origin, glm::vec3 dir, float tnear) {
    RTCRayHit rh{};
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace

Tracer::Tracer(const Scene& scene, const std::vector<bool>& doubleSided) : doubleSided_(doubleSided) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw Error(ExitCode::Failure, "Embree: cannot create a device (error " +
                                                     std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    for (const Instance& inst : scene.instances) {
        if (inst.mesh < 0 || size_t(inst.mesh) >= scene.meshes.size()) continue;
        for (const Primitive& p : scene.meshes[size_t(inst.mesh)].primitives) {
            if (p.indices.size() < 3 || p.vertices.empty()) continue;
            geometries_.push_back(flatten(p, inst.world));
            attach(device_, scene_, geometries_.back(), uint32_t(geometries_.size() - 1));
        }
    }
    rtcCommitScene(scene_);
}

Tracer::~Tracer() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

Hit Tracer::intersect(glm::vec3 origin, glm::vec3 dir, uint64_t& rays) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    float tnear = 0.0f;
    // A single-sided back face is skipped by restarting just past it; a handful of them in a row
    // only happens inside closed single-sided meshes.
    for (int attempt = 0; attempt < 16; ++attempt) {
        RTCRayHit rh = makeRay(origin, dir, tnear);
        rtcIntersect1(scene_, &context, &rh);
        ++rays;
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
        const Geometry& g = geometries_[rh.hit.geomID];
        const uint32_t* tri = &g.indices[size_t(rh.hit.primID) * 3];
        glm::vec3 a = g.positions[tri[0]], b = g.positions[tri[1]], c = g.positions[tri[2]];
        bool front = glm::dot(glm::cross(b - a, c - a), dir) < 0.0f;
        size_t material = g.material >= 0 && size_t(g.material) + 1 < doubleSided_.size()
                              ? size_t(g.material)
                              : doubleSided_.size() - 1;
        if (front || doubleSided_[material])
            return {true, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v};
        tnear = std::nextafter(rh.ray.tfar, std::numeric_limits<float>::infinity());
    }
    return {};
}

bool Tracer::occluded(glm::vec3 origin, glm::vec3 dir, uint64_t& rays) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray = makeRay(origin, dir, 0.0f).ray;
    rtcOccluded1(scene_, &context, &ray);
    ++rays;
    return ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

glm::vec3 offsetOrigin(glm::vec3 p, glm::vec3 geometricNormal, glm::vec3 dir) {
    float scale = std::max({1.0f, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    float side = glm::dot(geometricNormal, dir) >= 0.0f ? 1.0f : -1.0f;
    return p + geometricNormal * (side * 2e-4f * scale);
}

}  // namespace speculum::reference
