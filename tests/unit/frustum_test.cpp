// View-frustum culling on the CPU (engine/include/speculum/render/frustum.hpp): a culled box has
// no point in the clip volume (the images stay the same), and boxes a view cannot see are culled,
// for an ordinary camera and for a planar probe's mirrored one with its oblique near plane.
#include "speculum/probes/probes.hpp"
#include "speculum/render/frustum.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <random>

namespace speculum::render {
namespace {

// Some point of the box on a 9^3 grid lies in Vulkan's clip volume.
bool anyPointVisible(const CameraState& c, glm::vec3 lo, glm::vec3 hi) {
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j)
            for (int k = 0; k < 9; ++k) {
                glm::vec3 p = lo + (hi - lo) * glm::vec3(i, j, k) / 8.0f;
                glm::dvec4 q = glm::dmat4(c.viewProj) * glm::dvec4(glm::dvec3(p), 1.0);
                if (q.w > 0.0 && std::abs(q.x) <= q.w && std::abs(q.y) <= q.w && q.z >= 0.0 && q.z <= q.w) return true;
            }
    return false;
}

// Random boxes around the camera: none with a visible point is culled, and most without one are.
void expectConservativeAndUseful(const CameraState& c) {
    const Frustum f = frustumOf(c.viewProj);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> at(-6.0f, 6.0f), size(0.05f, 1.5f);
    int seen = 0, unseen = 0, culled = 0;
    for (int n = 0; n < 600; ++n) {
        glm::vec3 lo(at(rng), at(rng), at(rng)), hi = lo + glm::vec3(size(rng), size(rng), size(rng));
        bool vis = anyPointVisible(c, lo, hi);
        bool cull = outside(f, lo, hi);
        if (vis) {
            ++seen;
            EXPECT_FALSE(cull) << "a box with a visible point was culled";
        } else {
            ++unseen;
            culled += cull ? 1 : 0;
        }
    }
    EXPECT_GT(seen, 30);
    EXPECT_GT(unseen, 200);
    // Boxes that only straddle a corner of the volume are kept (conservative), and few are.
    EXPECT_GT(culled, unseen * 8 / 10) << culled << " of " << unseen << " invisible boxes culled";
}

TEST(Frustum, CullsOnlyBoxesWithNoVisiblePoint) {
    expectConservativeAndUseful(makeCamera({0.6f, 1.6f, 2.3f}, {-0.4f, 0.3f, -0.6f}, {0, 1, 0}, 0.95f, 320, 180));
}

TEST(Frustum, TheMirroredCameraCullsWhatLiesBehindTheMirror) {
    const CameraState view = makeCamera({0.6f, 1.6f, 2.3f}, {-0.4f, 0.3f, -0.6f}, {0, 1, 0}, 0.95f, 320, 180);
    CameraState mirrored;
    ASSERT_TRUE(probes::mirroredCamera(view, {0.0f, 1.0f, 0.0f, 0.0f}, 160, 90, 0.002f, mirrored));
    expectConservativeAndUseful(mirrored);
    const Frustum f = frustumOf(mirrored.viewProj);
    // Under the floor, right where the mirrored eye looks: clipped by the oblique near plane.
    EXPECT_TRUE(outside(f, {-1.0f, -1.0f, -1.0f}, {0.0f, -0.05f, 0.0f}));
    // The same box above the floor is what the mirror shows.
    EXPECT_FALSE(outside(f, {-1.0f, 0.05f, -1.0f}, {0.0f, 1.0f, 0.0f}));
}

TEST(Frustum, ABoxBehindTheCameraIsCulledAndOneAroundItIsNot) {
    const CameraState c = makeCamera({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.0f, 64, 64);
    const Frustum f = frustumOf(c.viewProj);
    EXPECT_TRUE(outside(f, {-1, -1, 1}, {1, 1, 3}));
    EXPECT_TRUE(outside(f, {5, -1, -3}, {6, 1, -2}));   // beside: right of the 1-radian cone
    EXPECT_FALSE(outside(f, {-1, -1, -1}, {1, 1, 1}));  // the camera inside the box
    EXPECT_FALSE(outside(f, {-0.1f, -0.1f, -1000.0f}, {0.1f, 0.1f, -999.0f}));  // far: the far plane is at infinity
}

TEST(Frustum, TransformBoxIsTheBoundsOfTheTransformedCorners) {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), {1.0f, -2.0f, 0.5f}) *
                  glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, -1))) *
                  glm::scale(glm::mat4(1.0f), {2.0f, -0.5f, 1.5f});
    glm::vec3 lo(-1.0f, 0.0f, -0.3f), hi(0.5f, 2.0f, 0.3f), wlo, whi;
    transformBox(m, lo, hi, wlo, whi);
    glm::vec3 elo(1e9f), ehi(-1e9f);
    for (int i = 0; i < 8; ++i) {
        glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        glm::vec3 w = glm::vec3(m * glm::vec4(c, 1.0f));
        elo = glm::min(elo, w), ehi = glm::max(ehi, w);
    }
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(wlo[a], elo[a], 1e-5f);
        EXPECT_NEAR(whi[a], ehi[a], 1e-5f);
    }
}

}  // namespace
}  // namespace speculum::render
