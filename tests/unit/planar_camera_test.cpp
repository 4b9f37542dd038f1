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

// The crop (planar.cpp, cropCamera): a texel of the cropped camera sees along the ray of the
// full camera's texel it stands for, so the planar image holds the same values where it is
// rendered; a point projects into the crop where the full image puts it, less the offset.
TEST(PlanarCamera, CropKeepsEveryTexelsRay) {
    Fixture f;
    const TexelRect rect{23, 11, 101, 64};
    const render::CameraState crop = cropCamera(f.mirrored, rect);
    ASSERT_EQ(crop.width, 78u);
    ASSERT_EQ(crop.height, 53u);
    for (uint32_t y = rect.y0; y < rect.y1; y += 7)
        for (uint32_t x = rect.x0; x < rect.x1; x += 5) {
            glm::vec3 o0, d0, o1, d1;
            render::primaryRay(f.mirrored, float(x), float(y), o0, d0);
            render::primaryRay(crop, float(x - rect.x0), float(y - rect.y0), o1, d1);
            EXPECT_NEAR(glm::distance(d0, d1), 0.0f, 1e-5f) << x << " " << y;
            // The origin lies on the oblique near plane, the mirror 2-4 m off: float32 matrices.
            EXPECT_NEAR(glm::distance(o0, o1), 0.0f, 1e-3f) << x << " " << y;
        }
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-2.5f, 2.5f), h(0.1f, 2.0f);
    for (int i = 0; i < 50; ++i) {
        const glm::vec3 p(u(rng), h(rng), u(rng));
        const glm::dvec4 a = clipOf(f.mirrored, p), b = clipOf(crop, p);
        if (!(a.w > 0.0)) continue;
        const glm::dvec2 full = (glm::dvec2(a) / a.w * 0.5 + 0.5) * glm::dvec2(160, 90);
        const glm::dvec2 cropped = (glm::dvec2(b) / b.w * 0.5 + 0.5) * glm::dvec2(78, 53);
        EXPECT_NEAR(cropped.x, full.x - rect.x0, 1e-3) << i;
        EXPECT_NEAR(cropped.y, full.y - rect.y0, 1e-3) << i;
        EXPECT_NEAR(b.z / b.w, a.z / a.w, 1e-6) << i;  // depth unchanged
    }
    // The whole image is the camera itself.
    const render::CameraState same = cropCamera(f.mirrored, {0, 0, 160, 90});
    EXPECT_EQ(same.viewProj, f.mirrored.viewProj);
}

// The footprint (planarFootprint): every point of the rectangle the view sees lands inside it,
// it is tight (no margin asked, a rectangle wholly on screen: the texels its corners fall in),
// a floor running under the camera is clipped at the near plane rather than projected through
// it, and a rectangle behind the camera has none.
TEST(PlanarCamera, FootprintIsTheRectanglesTexelsOnScreen) {
    PlanarInfo info;
    info.origin = {0.5f, 0.0f, -2.0f};
    info.plane = {0.0f, 1.0f, 0.0f, 0.0f};
    info.probe.extents = {1.5f, 1.0f, 0.0f};
    const uint32_t w = 160, h = 90;
    render::CameraState view = render::makeCamera({0.0f, 1.6f, 1.0f}, {0.4f, 0.2f, -2.0f}, {0, 1, 0}, 0.95f, w, h);
    const TexelRect r = planarFootprint(view.viewProj, info, w, h, 0);
    ASSERT_FALSE(r.empty());
    EXPECT_LT(r.x1 - r.x0, w);  // a part of the view, not all of it
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 4000; ++i) {
        const glm::vec3 p = info.origin + glm::vec3(u(rng) * 1.5f, 0.0f, u(rng) * 1.0f);
        const glm::dvec4 c = clipOf(view, p);
        if (!visible(c)) continue;
        const glm::dvec2 t = (glm::dvec2(c) / c.w * 0.5 + 0.5) * glm::dvec2(w, h);
        EXPECT_TRUE(t.x >= r.x0 && t.x <= r.x1 && t.y >= r.y0 && t.y <= r.y1) << t.x << " " << t.y;
    }
    glm::dvec2 lo(1e9), hi(-1e9);
    for (float cx : {-1.0f, 1.0f})
        for (float cz : {-1.0f, 1.0f}) {
            const glm::dvec4 c = clipOf(view, info.origin + glm::vec3(cx * 1.5f, 0.0f, cz * 1.0f));
            ASSERT_TRUE(visible(c));
            const glm::dvec2 t = (glm::dvec2(c) / c.w * 0.5 + 0.5) * glm::dvec2(w, h);
            lo = glm::min(lo, t);
            hi = glm::max(hi, t);
        }
    EXPECT_EQ(r.x0, uint32_t(std::floor(lo.x)));
    EXPECT_EQ(r.y0, uint32_t(std::floor(lo.y)));
    EXPECT_EQ(r.x1, uint32_t(std::ceil(hi.x)));
    EXPECT_EQ(r.y1, uint32_t(std::ceil(hi.y)));
    // A margin grows it, within the image.
    const TexelRect m = planarFootprint(view.viewProj, info, w, h, 12);
    EXPECT_EQ(m.x0, r.x0 >= 12 ? r.x0 - 12 : 0u);
    EXPECT_EQ(m.y1, std::min(r.y1 + 12, h));
    // A floor under the camera reaches the image's bottom and sides; one behind it has none.
    PlanarInfo floor = info;
    floor.origin = {0.0f, 0.0f, 0.0f};
    floor.probe.extents = {20.0f, 20.0f, 0.0f};
    const TexelRect under = planarFootprint(view.viewProj, floor, w, h, 0);
    EXPECT_EQ(under.x0, 0u);
    EXPECT_EQ(under.x1, w);
    EXPECT_GT(under.y1 - under.y0, h / 3);
    // A strip on the floor right of the view's axis, from behind the camera to 3 m ahead: its
    // part in front lies in the right half of the image. Its corners behind the camera,
    // projected without the near plane's clip, would land on the left.
    PlanarInfo strip = info;
    strip.origin = {1.2f, 0.0f, 0.0f};
    strip.probe.extents = {0.2f, 3.0f, 0.0f};
    const TexelRect side = planarFootprint(view.viewProj, strip, w, h, 0);
    ASSERT_FALSE(side.empty());
    EXPECT_GT(side.x0, w / 2) << side.x0 << " " << side.x1;
    EXPECT_EQ(side.y1, h);
    PlanarInfo behind = info;
    behind.origin = {0.0f, 0.0f, 6.0f};
    behind.probe.extents = {1.0f, 1.0f, 0.0f};
    EXPECT_TRUE(planarFootprint(view.viewProj, behind, w, h, 0).empty());
}

}  // namespace
}  // namespace speculum::probes
