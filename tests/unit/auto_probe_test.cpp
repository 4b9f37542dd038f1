// probes.auto_probe on the CPU (modules/probes/probes.cpp): which scenes count as unconfigured,
// and the box fitted to one (its accuracy gain is accuracy.plain_metals.main.probe_gain's).
#include "speculum/probes/probes.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

namespace speculum::probes {
namespace {

// A primitive with two vertices at its bounds' corners (an empty one has no bounds).
Primitive box(glm::vec3 lo, glm::vec3 hi) {
    Primitive p;
    p.vertices.resize(2);
    p.vertices[0].position = lo;
    p.vertices[1].position = hi;
    p.boundsMin = lo;
    p.boundsMax = hi;
    return p;
}

// A plain export's shape: a 16 x 16 m floor at y = 0 (one primitive) and a 2 x 6 x 2 m block
// standing on it (another, at its node's offset) around the box's centre, where
// cube_camera_repro's cube holds it.
Scene plainScene() {
    Scene s;
    s.nodes.resize(2);
    s.materials.resize(2);
    s.meshes.resize(2);
    s.meshes[0].primitives.push_back(box({-8.0f, 0.0f, -6.0f}, {8.0f, 0.0f, 10.0f}));
    s.meshes[1].primitives.push_back(box({-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}));
    s.instances.push_back({0, 0, glm::mat4(1.0f)});
    s.instances.push_back({1, 1, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 3.0f, 2.0f)) *
                                     glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 3.0f, 1.0f))});
    s.boundsMin = {-8.0f, 0.0f, -6.0f};
    s.boundsMax = {8.0f, 6.0f, 10.0f};
    return s;
}

TEST(AutoProbe, OnlyASceneWithoutALocalProbeAndWithBoundsWantsOne) {
    EXPECT_TRUE(wantsAutoProbe(plainScene()));
    Scene local = plainScene();
    local.nodes[1].probe = ReflectionProbe{.kind = ProbeKind::LocalCubemap};
    local.roots = {0, 1};
    EXPECT_FALSE(wantsAutoProbe(local)) << "a placed local probe replaces the automatic one";
    Scene inactive = local;
    inactive.roots = {0};
    EXPECT_TRUE(wantsAutoProbe(inactive)) << "a probe outside the active scene is not the scene's";
    for (ProbeKind kind : {ProbeKind::Cmo, ProbeKind::Planar}) {
        Scene above = plainScene();
        above.nodes[1].probe = ReflectionProbe{.kind = kind};
        above.roots = {0, 1};
        EXPECT_TRUE(wantsAutoProbe(above)) << kProbeKindNames[size_t(kind)] << " sits above the local probes";
    }
    Scene empty = plainScene();
    empty.instances.clear();
    EXPECT_FALSE(wantsAutoProbe(empty)) << "nothing to fit a box to";
    Scene flat = plainScene();
    flat.boundsMax.x = flat.boundsMin.x;
    EXPECT_FALSE(wantsAutoProbe(flat)) << "a box with no width";
}

TEST(AutoProbe, TheBoxHoldsTheBoundsStandsOnTheirFloorAndIsHalfAsTallAsWide) {
    const Scene s = plainScene();
    const ProbeInfo p = autoProbe(s);
    EXPECT_EQ(p.node, -1);
    EXPECT_EQ(p.probe.kind, ProbeKind::LocalCubemap);
    EXPECT_EQ(p.probe.shape, ProbeShape::Box);
    EXPECT_EQ(p.probe.update, ProbeUpdate::Once);
    const glm::vec3 e = p.probe.extents;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 w((corner & 1) ? s.boundsMax.x : s.boundsMin.x, (corner & 2) ? s.boundsMax.y : s.boundsMin.y,
                          (corner & 4) ? s.boundsMax.z : s.boundsMin.z);
        const glm::vec3 local(p.gpu.worldToLocal * glm::vec4(w, 1.0f));
        EXPECT_TRUE(glm::all(glm::lessThanEqual(glm::abs(local), e))) << "corner " << corner << " outside the box";
    }
    // The box's centre in world space (the capture point is apart from it: next test).
    const glm::vec3 centre(glm::inverse(p.gpu.worldToLocal)[3]);
    // The floor: within 1% of the bounds' height below theirs (inside, never above it).
    EXPECT_LE(centre.y - e.y, s.boundsMin.y);
    EXPECT_GE(centre.y - e.y, s.boundsMin.y - 0.011f * (s.boundsMax.y - s.boundsMin.y));
    EXPECT_NEAR(centre.x, 0.0f, 1e-5f);
    EXPECT_NEAR(centre.z, 2.0f, 1e-5f);
    // At least half as tall as wide: 16 m across, so at least 8 m tall.
    EXPECT_GE(2.0f * e.y, 0.5f * 2.0f * std::max(e.x, e.z) - 1e-4f);
    EXPECT_NEAR(p.volume, 8.0f * e.x * e.y * e.z, 1e-3f * p.volume);
}

TEST(AutoProbe, TheCapturePointClimbsOutOfTheBlockThatHoldsTheCentre) {
    const Scene s = plainScene();
    const ProbeInfo p = autoProbe(s);
    const glm::vec3 centre(glm::inverse(p.gpu.worldToLocal)[3]), eye(p.gpu.center);
    ASSERT_LT(centre.y, 6.0f) << "the fixture's block (y 0 .. 6 m) must hold the box's centre";
    EXPECT_EQ(eye.x, centre.x);
    EXPECT_EQ(eye.z, centre.z);
    // Halfway from the block's top (6 m) to the box's.
    EXPECT_NEAR(eye.y, 0.5f * (6.0f + centre.y + p.probe.extents.y), 1e-4f) << "not halfway above the block";
    // Without the block the centre is in the open and is the capture point.
    Scene open = s;
    open.instances.pop_back();
    const ProbeInfo q = autoProbe(open);
    EXPECT_EQ(glm::vec3(q.gpu.center), glm::vec3(glm::inverse(q.gpu.worldToLocal)[3]));
}

}  // namespace
}  // namespace speculum::probes
