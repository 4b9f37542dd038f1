// Movement and collision against levels with known answers (no device).
#include "player.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace speculum::game {
namespace {

constexpr float kPi = 3.14159265f;

// A floor from -10 to 10 (top at y = 0).
Level floorLevel() {
    Level level;
    level.addBox({-10.0f, -1.0f, -10.0f}, {10.0f, 0.0f, 10.0f});
    return level;
}

void run(const Level& level, const PlayerParams& p, Player& player, const MoveInput& in, float seconds,
         StepEvents* any = nullptr) {
    for (int i = 0; i < int(std::lround(seconds / kStep)); ++i) {
        StepEvents e = step(level, p, player, in);
        if (any) {
            any->hitWall |= e.hitWall;
            any->hitCeiling |= e.hitCeiling;
            any->landed |= e.landed;
        }
    }
}

TEST(GamePlayer, ClosestPointOnTriangleRegions) {
    Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {}, {}};
    auto near = [](glm::vec3 a, glm::vec3 b) { return glm::length(a - b) < 1e-6f; };
    EXPECT_TRUE(near(closestPointOnTriangle({0.2f, 0.2f, 5.0f}, t), {0.2f, 0.2f, 0.0f}));  // face
    EXPECT_TRUE(near(closestPointOnTriangle({-1.0f, -1.0f, 0.0f}, t), glm::vec3(0.0f)));   // vertex a
    EXPECT_TRUE(near(closestPointOnTriangle({0.5f, -2.0f, 1.0f}, t), {0.5f, 0.0f, 0.0f})); // edge ab
    glm::vec3 q = closestPointOnTriangle({1.0f, 1.0f, 0.0f}, t);                             // edge bc
    EXPECT_NEAR(q.x, 0.5f, 1e-6f);
    EXPECT_NEAR(q.y, 0.5f, 1e-6f);
}

TEST(GamePlayer, StandsOnTheFloor) {
    Level level = floorLevel();
    PlayerParams p;
    Player player{.feet = {0.0f, 1.0f, 0.0f}};
    StepEvents any;
    run(level, p, player, {}, 2.0f, &any);
    EXPECT_TRUE(player.grounded);
    EXPECT_TRUE(any.landed);
    EXPECT_NEAR(player.feet.y, 0.0f, 0.01f);
    EXPECT_NEAR(player.feet.x, 0.0f, 1e-4f);
    EXPECT_NEAR(player.feet.z, 0.0f, 1e-4f);
}

TEST(GamePlayer, WalkingIntoACornerStopsAtBothWalls) {
    Level level = floorLevel();
    level.addBox({2.0f, 0.0f, -10.0f}, {3.0f, 3.0f, 10.0f});    // wall at x = 2
    level.addBox({-10.0f, 0.0f, -3.0f}, {10.0f, 3.0f, -2.0f});  // wall at z = -2
    PlayerParams p;
    Player player{.feet = {0.0f, 0.0f, 0.0f}};
    // Yaw -45 degrees looks towards +x, -z: straight into the corner.
    MoveInput in{.move = {0.0f, 1.0f}, .yaw = -kPi / 4.0f};
    StepEvents any;
    run(level, p, player, in, 3.0f, &any);
    EXPECT_TRUE(any.hitWall);
    EXPECT_NEAR(player.feet.x, 2.0f - p.radius, 0.01f);
    EXPECT_NEAR(player.feet.z, -2.0f + p.radius, 0.01f);
    EXPECT_NEAR(player.feet.y, 0.0f, 0.01f);
}

TEST(GamePlayer, SlidesAlongAWall) {
    Level level = floorLevel();
    level.addBox({2.0f, 0.0f, -10.0f}, {3.0f, 3.0f, 10.0f});
    PlayerParams p;
    Player player{.feet = {0.0f, 0.0f, 0.0f}};
    MoveInput in{.move = {0.0f, 1.0f}, .yaw = -kPi / 4.0f};
    run(level, p, player, in, 1.0f);
    // Into the wall at 45 degrees: stopped in x, still walking in -z at the speed's z share.
    EXPECT_NEAR(player.feet.x, 2.0f - p.radius, 0.01f);
    EXPECT_LT(player.feet.z, -1.5f);
}

TEST(GamePlayer, SteppingOffALedgeFalls) {
    Level level;
    level.addBox({-10.0f, 1.0f, -10.0f}, {0.0f, 2.0f, 10.0f});  // a platform, top y = 2, edge at x = 0
    level.addBox({-10.0f, -1.0f, -10.0f}, {10.0f, 0.0f, 10.0f}); // the floor below, top y = 0
    PlayerParams p;
    Player player{.feet = {-1.0f, 2.0f, 0.0f}};
    run(level, p, player, {}, 0.2f);
    ASSERT_TRUE(player.grounded);
    ASSERT_NEAR(player.feet.y, 2.0f, 0.01f);
    // Walk towards +x (yaw -90 degrees) for 1 s: off the edge after about 0.33 s.
    MoveInput in{.move = {0.0f, 1.0f}, .yaw = -kPi / 2.0f};
    bool fell = false;
    for (int i = 0; i < 60; ++i) {
        step(level, p, player, in);
        fell = fell || (!player.grounded && player.feet.y < 1.9f);
    }
    EXPECT_TRUE(fell);
    run(level, p, player, {}, 1.0f);
    EXPECT_TRUE(player.grounded);
    EXPECT_NEAR(player.feet.y, 0.0f, 0.01f);
    EXPECT_GT(player.feet.x, 0.0f);
}

TEST(GamePlayer, JumpReachesItsHeightInTheOpen) {
    Level level = floorLevel();
    PlayerParams p;
    Player player{.feet = {0.0f, 0.0f, 0.0f}};
    run(level, p, player, {}, 0.2f);
    float top = 0.0f;
    step(level, p, player, {.jump = true});
    for (int i = 0; i < 120; ++i) {
        step(level, p, player, {});
        top = std::max(top, player.feet.y);
    }
    // v^2 / 2g, less what the discrete steps lose.
    float expected = p.jumpSpeed * p.jumpSpeed / (2.0f * p.gravity);
    EXPECT_NEAR(top, expected, 0.05f);
    EXPECT_TRUE(player.grounded);
}

TEST(GamePlayer, JumpingUnderALowCeilingStopsAtIt) {
    Level level = floorLevel();
    level.addBox({-10.0f, 2.0f, -10.0f}, {10.0f, 3.0f, 10.0f});  // ceiling underside at y = 2
    PlayerParams p;
    Player player{.feet = {0.0f, 0.0f, 0.0f}};
    run(level, p, player, {}, 0.2f);
    float top = 0.0f;
    StepEvents any;
    step(level, p, player, {.jump = true});
    for (int i = 0; i < 120; ++i) {
        StepEvents e = step(level, p, player, {});
        any.hitCeiling |= e.hitCeiling;
        top = std::max(top, player.feet.y + p.height);
    }
    EXPECT_TRUE(any.hitCeiling);
    EXPECT_NEAR(top, 2.0f, 0.01f);  // the head stops at the ceiling: 0.3 m of the 0.9 m jump
    EXPECT_TRUE(player.grounded);
    EXPECT_NEAR(player.feet.y, 0.0f, 0.01f);
}

TEST(GamePlayer, NoJumpInTheAir) {
    Level level = floorLevel();
    PlayerParams p;
    Player player{.feet = {0.0f, 5.0f, 0.0f}};
    step(level, p, player, {.jump = true});
    EXPECT_LT(player.velocity.y, 0.0f);
}

TEST(GamePlayer, LevelFromSceneAppliesInstanceTransforms) {
    Scene scene;
    Mesh mesh;
    Primitive prim;
    prim.vertices = {{{0, 0, 0}, {}, {}, {}}, {{1, 0, 0}, {}, {}, {}}, {{0, 0, 1}, {}, {}, {}}};
    prim.indices = {0, 1, 2};
    mesh.primitives.push_back(prim);
    scene.meshes.push_back(mesh);
    glm::mat4 moved(1.0f);
    moved[3] = glm::vec4(5.0f, 1.0f, 0.0f, 1.0f);
    scene.instances = {{0, 0, glm::mat4(1.0f)}, {1, 0, moved}};
    Level all = levelFromScene(scene);
    ASSERT_EQ(all.triangles.size(), 2u);
    EXPECT_EQ(all.triangles[1].a, glm::vec3(5.0f, 1.0f, 0.0f));
    Level some = levelFromScene(scene, [](int node) { return node != 1; });
    EXPECT_EQ(some.triangles.size(), 1u);
}

TEST(GamePlayer, SameInputsSamePath) {
    Level level = floorLevel();
    level.addBox({2.0f, 0.0f, -10.0f}, {3.0f, 3.0f, 10.0f});
    PlayerParams p;
    Player a{.feet = {0.0f, 0.0f, 0.0f}}, b = a;
    for (int i = 0; i < 300; ++i) {
        MoveInput in{.move = {std::sin(0.1f * float(i)), 1.0f}, .yaw = 0.01f * float(i), .jump = i % 50 == 0};
        step(level, p, a, in);
        step(level, p, b, in);
    }
    EXPECT_EQ(a.feet, b.feet);
    EXPECT_EQ(a.velocity, b.velocity);
}

}  // namespace
}  // namespace speculum::game
