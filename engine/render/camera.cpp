// Camera conventions (renderer.hpp): reversed-Z with an infinite far plane, Vulkan clip space
// with y down, pixel centres at (x + 0.5) / w. primaryRay() and shaders/common/camera.glsl must
// stay twins: the reference renderer traces exactly the rays the rasterizer samples.
#include "speculum/render/renderer.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace speculum::render {
namespace {

// Right-handed view space (camera looks down -Z). clip.z = znear and clip.w = -z give
// depth = znear / -z: 1 at the near plane, 0 at infinity. The y row is negated so that view
// +Y lands at the top of the framebuffer.
glm::mat4 perspectiveReversedInfinite(float yfov, float aspect, float znear) {
    float f = 1.0f / std::tan(yfov * 0.5f);
    glm::mat4 p(0.0f);
    p[0][0] = f / aspect;
    p[1][1] = -f;
    p[2][3] = -1.0f;
    p[3][2] = znear;
    return p;
}

// Orthographic with reversed Z: depth 1 at znear, 0 at zfar.
glm::mat4 orthographicReversed(float xmag, float ymag, float znear, float zfar) {
    glm::mat4 p(1.0f);
    p[0][0] = 1.0f / xmag;
    p[1][1] = -1.0f / ymag;
    p[2][2] = 1.0f / (zfar - znear);
    p[3][2] = zfar / (zfar - znear);
    return p;
}

CameraState finish(const glm::mat4& view, const glm::mat4& proj, float yfov, float znear,
                   uint32_t width, uint32_t height) {
    CameraState c;
    c.view = view;
    c.proj = proj;
    c.viewProj = proj * view;
    // Inverted in double: the infinite projection makes the float inverse lose digits that the
    // reference renderer's rays would then disagree on.
    c.invViewProj = glm::mat4(glm::inverse(glm::dmat4(c.viewProj)));
    c.position = glm::vec3(glm::inverse(glm::dmat4(view))[3]);
    c.yfov = yfov;
    c.znear = znear;
    c.width = std::max(width, 1u);
    c.height = std::max(height, 1u);
    return c;
}

glm::dvec3 unproject(const glm::dmat4& invViewProj, double ndcX, double ndcY, double depth) {
    glm::dvec4 p = invViewProj * glm::dvec4(ndcX, ndcY, depth, 1.0);
    return glm::dvec3(p) / p.w;
}

}  // namespace

glm::mat4 orthographicShadowProjection(float halfExtent, float znear, float zfar) {
    return orthographicReversed(halfExtent, halfExtent, znear, zfar);
}

CameraState makeCamera(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float yfovRadians,
                       uint32_t width, uint32_t height, float znear) {
    float aspect = float(std::max(width, 1u)) / float(std::max(height, 1u));
    glm::mat4 view = glm::lookAt(eye, target, up);
    return finish(view, perspectiveReversedInfinite(yfovRadians, aspect, znear), yfovRadians, znear,
                  width, height);
}

CameraState makeCamera(const Camera& camera, uint32_t width, uint32_t height) {
    glm::mat4 view = glm::mat4(glm::inverse(glm::dmat4(camera.world)));
    float znear = camera.znear > 0.0f ? camera.znear : 0.05f;
    if (!camera.perspective) {
        // glTF requires zfar for orthographic cameras; a missing one gets a generous default.
        float zfar = camera.zfar > znear ? camera.zfar : znear + 1000.0f;
        return finish(view, orthographicReversed(camera.xmag, camera.ymag, znear, zfar), 0.0f,
                      znear, width, height);
    }
    float aspect = camera.aspectRatio > 0.0f
                       ? camera.aspectRatio
                       : float(std::max(width, 1u)) / float(std::max(height, 1u));
    return finish(view, perspectiveReversedInfinite(camera.yfov, aspect, znear), camera.yfov, znear,
                  width, height);
}

CameraState frameBounds(const Scene& scene, uint32_t width, uint32_t height) {
    glm::vec3 center = (scene.boundsMin + scene.boundsMax) * 0.5f;
    float radius = std::max(glm::length(scene.boundsMax - scene.boundsMin) * 0.5f, 1e-3f);
    const float yfov = 0.8f;
    float aspect = float(std::max(width, 1u)) / float(std::max(height, 1u));
    // The bounding sphere must fit the narrower of the two fields of view.
    float halfFov = std::min(yfov * 0.5f, std::atan(std::tan(yfov * 0.5f) * aspect));
    float distance = radius / std::sin(halfFov) * 1.05f;
    glm::vec3 dir = glm::normalize(glm::vec3(1.0f, 0.6f, 1.0f));
    float znear = std::clamp(radius * 0.01f, 1e-3f, 0.05f);
    return makeCamera(center + dir * distance, center, glm::vec3(0, 1, 0), yfov, width, height,
                      znear);
}

void primaryRay(const CameraState& camera, float px, float py, glm::vec3& origin,
                glm::vec3& direction) {
    double ndcX = (double(px) + 0.5) / double(camera.width) * 2.0 - 1.0;
    double ndcY = (double(py) + 0.5) / double(camera.height) * 2.0 - 1.0;
    glm::dmat4 inv(camera.invViewProj);
    // Two points on the ray rather than eye + direction, so orthographic cameras work too; the
    // origin sits on the near plane, where the rasterizer clips.
    glm::dvec3 nearPoint = unproject(inv, ndcX, ndcY, 1.0);
    glm::dvec3 farPoint = unproject(inv, ndcX, ndcY, 0.5);
    origin = glm::vec3(nearPoint);
    direction = glm::vec3(glm::normalize(farPoint - nearPoint));
}

}  // namespace speculum::render
