// A planar probe's mirrored camera on the CPU (modules/probes/planar.cpp): the reflection fixes
// the plane's points, the oblique near plane clips exactly what lies behind the mirror, and
// reversed-Z depth still orders every ray's points.
#include "speculum/probes/probes.hpp"

#include <gtest/gtest.h>

#include <random>

namespace speculum::probes {
namespace {

glm::dvec4 clipOf(const render::CameraState& c, glm::vec3 p) {
    return glm::dmat4(c.viewProj) * glm::dvec4(glm::dvec3(p), 1.0);
}

// Inside Vulkan's clip volume: -w <= x, y <= w and 0 <= z <= w.
bool visible(const glm::dvec4& c) {
    return c.w > 0.0 && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w && c.z >= 0.0 && c.z <= c.w;
}

struct Fixture {
    glm::vec4 plane{0.0f, 1.0f, 0.0f, 0.0f};  // the floor y = 0
    render::CameraState view = render::makeCamera({0.6f, 1.6f, 2.3f}, {-0.4f, 0.3f, -0.6f}, {0, 1, 0}, 0.95f, 320, 180);
    render::CameraState mirrored;
    Fixture() { EXPECT_TRUE(mirroredCamera(view, plane, 160, 90, 0.002f, mirrored)); }
};

TEST(PlanarCamera, ReflectionMatrixMirrorsAndFixesThePlane) {
    const glm::vec4 plane(glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f)), -0.7f);
    const glm::mat4 m = reflectionMatrix(plane);
    const glm::vec3 n(plane);
    const glm::vec3 onPlane = -plane.w * n + glm::vec3(0.4f, 0.0f, 0.0f) - glm::dot(glm::vec3(0.4f, 0, 0), n) * n;
    EXPECT_NEAR(glm::distance(glm::vec3(m * glm::vec4(onPlane, 1.0f)), onPlane), 0.0f, 1e-5f);
    const glm::vec3 above = onPlane + 0.8f * n;
    EXPECT_NEAR(glm::distance(glm::vec3(m * glm::vec4(above, 1.0f)), onPlane - 0.8f * n), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::determinant(glm::mat3(m)), -1.0f, 1e-5f);
}

TEST(PlanarCamera, PlanePointsProjectWhereTheViewSeesThem) {
    Fixture f;
    EXPECT_NEAR(f.mirrored.position.y, -1.6f, 1e-5f);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2.5f, 2.5f);
    int checked = 0;
    for (int i = 0; i < 200; ++i) {
        glm::vec3 p(u(rng), 0.0f, u(rng));
        glm::dvec4 a = clipOf(f.view, p), b = clipOf(f.mirrored, p);
        if (!(a.w > 0.0)) continue;
        ++checked;
        EXPECT_NEAR(a.x / a.w, b.x / b.w, 1e-4) << i;
        EXPECT_NEAR(a.y / a.w, b.y / b.w, 1e-4) << i;
    }
    EXPECT_GT(checked, 100);
}

TEST(PlanarCamera, ObliqueNearPlaneClipsWhatLiesBehindTheMirror) {
    Fixture f;
    // Points the view sees reflected: the mirror images (below the floor) of points above it.
    // Above the floor by more than the 2 mm offset they are drawn; below, never.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-2.5f, 2.5f), h(0.01f, 3.0f);
    int drawn = 0;
    for (int i = 0; i < 500; ++i) {
        glm::vec3 p(u(rng), h(rng), u(rng));
        glm::vec3 below(p.x, -p.y, p.z);
        glm::dvec4 unclipped = glm::dmat4(f.mirrored.proj) * glm::dmat4(f.mirrored.view) * glm::dvec4(glm::dvec3(p), 1.0);
        // In the mirrored camera's frustum (x, y) the point above is kept by the depth range...
        if (unclipped.w > 0.0 && std::abs(unclipped.x) <= unclipped.w && std::abs(unclipped.y) <= unclipped.w) {
            EXPECT_TRUE(visible(unclipped)) << "above the mirror but clipped: " << p.x << " " << p.y << " " << p.z;
            drawn += visible(unclipped);
        }
        // ...and what lies below the floor is outside the depth range wherever it projects.
        glm::dvec4 c = clipOf(f.mirrored, below);
        EXPECT_FALSE(visible(c)) << "behind the mirror but drawn: " << below.x << " " << below.y << " " << below.z;
    }
    EXPECT_GT(drawn, 50);
    // The floor itself (on the plane, under the 2 mm offset) is clipped too.
    EXPECT_FALSE(visible(clipOf(f.mirrored, {-0.4f, 0.0f, -0.6f})));
}

TEST(PlanarCamera, DepthFallsAlongEveryRay) {
    Fixture f;
    const glm::dvec3 eye(f.mirrored.position);
    for (glm::vec3 target : {glm::vec3(-0.4f, 0.3f, -0.6f), glm::vec3(2.0f, 2.9f, -2.4f), glm::vec3(-2.9f, 0.05f, 1.0f)}) {
        glm::dvec3 dir = glm::normalize(glm::dvec3(target) - eye);
        double last = 2.0;
        for (double t = 2.0; t < 200.0; t *= 1.3) {
            glm::dvec4 c = glm::dmat4(f.mirrored.viewProj) * glm::dvec4(eye + dir * t, 1.0);
            if (c.z > c.w) continue;  // still behind the mirror
            double depth = c.z / c.w;
            EXPECT_LT(depth, last);
            EXPECT_GE(depth, 0.0);
            last = depth;
        }
    }
}

TEST(PlanarCamera, RefusesAnEyeBehindThePlaneAndOrthographicViews) {
    render::CameraState below = render::makeCamera({0.0f, -1.0f, 2.0f}, {0, -1, 0}, {0, 1, 0}, 0.95f, 64, 64);
    render::CameraState out;
    EXPECT_FALSE(mirroredCamera(below, {0, 1, 0, 0}, 32, 32, 0.002f, out));
    render::CameraState ortho = render::makeCamera({0.0f, 2.0f, 2.0f}, {0, 0, 0}, {0, 1, 0}, 0.95f, 64, 64);
    ortho.proj[2][3] = 0.0f;
    ortho.proj[3][3] = 1.0f;
    EXPECT_FALSE(mirroredCamera(ortho, {0, 1, 0, 0}, 32, 32, 0.002f, out));
}

// The ground's camera (probes.ground_store, shaders/ground.glsl): a tilted planar probe's
// rectangle fills the image exactly, its points at depth 0.5; 3 cm off the plane is clipped,
// and the winding matches the view's (the floor's front faces stay front faces).
TEST(PlanarCamera, GroundFillsTheRectangleAndClipsOffThePlane) {
    PlanarInfo info;
    info.normal = glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f));
    info.axisX = glm::normalize(glm::cross(glm::vec3(0, 0, 1), info.normal));
    info.axisZ = glm::cross(info.axisX, info.normal);
    info.origin = {0.5f, 0.3f, -1.0f};
    info.plane = glm::vec4(info.normal, -glm::dot(info.normal, info.origin));
    info.probe.extents = {4.0f, 3.0f, 0.0f};
    const render::CameraState c = groundCamera(info, 128);
    auto at = [&](float x, float z, float up) {
        return info.origin + x * info.axisX + z * info.axisZ + up * info.normal;
    };
    for (float sx : {-1.0f, 1.0f})
        for (float sz : {-1.0f, 1.0f}) {
            glm::dvec4 q = clipOf(c, at(sx * 4.0f, sz * 3.0f, 0.0f));
            EXPECT_NEAR(std::abs(q.x / q.w), 1.0, 1e-5);
            EXPECT_NEAR(std::abs(q.y / q.w), 1.0, 1e-5);
            EXPECT_NEAR(q.z / q.w, 0.5, 1e-4);
        }
    EXPECT_TRUE(visible(clipOf(c, at(1.0f, -2.0f, 0.015f))));
    EXPECT_TRUE(visible(clipOf(c, at(1.0f, -2.0f, -0.015f))));
    EXPECT_FALSE(visible(clipOf(c, at(1.0f, -2.0f, 0.03f))));
    EXPECT_FALSE(visible(clipOf(c, at(1.0f, -2.0f, -0.03f))));
    EXPECT_FALSE(visible(clipOf(c, at(4.2f, 0.0f, 0.0f))));
    // Seen from above the plane, a triangle wound counter-clockwise about the normal keeps the
    // sign of its screen-space area that a perspective view from above gives it.
    auto area = [&](const render::CameraState& cam) {
        glm::dvec4 a = clipOf(cam, at(0, 0, 0)), b = clipOf(cam, at(1, 0, 0)), d = clipOf(cam, at(0, -1, 0));
        glm::dvec2 p0(a / a.w), p1(b / b.w), p2(d / d.w);
        return (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
    };
    const render::CameraState persp =
        render::makeCamera(at(0.3f, 0.2f, 3.0f), info.origin, info.axisZ, 0.9f, 128, 128);
    EXPECT_GT(area(c) * area(persp), 0.0) << area(c) << " " << area(persp);
}

}  // namespace
}  // namespace speculum::probes
