// The game's movement and collision, on the CPU and without a device: a walking player (a capsule
// approximated by three spheres on its axis) against the level's triangles, with gravity, a jump
// and ledges to step off. The simulation runs at a fixed step, so a replay of the same inputs
// gives the same positions (sample_game/README.md).
#pragma once

#include "speculum/scene.hpp"

#include <glm/glm.hpp>

#include <functional>
#include <vector>

namespace speculum::game {

struct Triangle {
    glm::vec3 a, b, c;
    glm::vec3 lo, hi;  // bounds
};

struct Level {
    std::vector<Triangle> triangles;
    void add(glm::vec3 a, glm::vec3 b, glm::vec3 c);
    // An axis-aligned box as twelve triangles (tests and simple levels).
    void addBox(glm::vec3 lo, glm::vec3 hi);
};

// The triangles of every instance whose node `solid` accepts (all when `solid` is empty), in world
// space.
Level levelFromScene(const Scene& scene, const std::function<bool(int node)>& solid = {});

struct PlayerParams {
    float radius = 0.3f;
    float height = 1.7f;      // feet to the top of the head
    float eyeHeight = 1.6f;   // feet to the eye
    float walkSpeed = 3.0f;   // m/s
    float gravity = 9.81f;    // m/s^2
    float jumpSpeed = 4.2f;   // m/s upwards: a jump of about 0.9 m
    float groundSlope = 0.7f; // a contact whose normal has y above this is ground (about 45 degrees)
};

// What the player asks for in one step: move (x right, y forward, each -1..1) relative to `yaw`.
struct MoveInput {
    glm::vec2 move{0.0f};
    float yaw = 0.0f;  // radians, 0 looks down -Z (as the game's camera)
    bool jump = false;
};

// What happened in one step: the contacts' normals the game reports (a wall hit, the ground).
struct StepEvents {
    bool hitWall = false;
    bool hitCeiling = false;
    bool landed = false;
};

struct Player {
    glm::vec3 feet{0.0f};
    glm::vec3 velocity{0.0f};
    bool grounded = false;
    glm::vec3 eye(const PlayerParams& p) const { return feet + glm::vec3(0.0f, p.eyeHeight, 0.0f); }
};

// The simulation's step, in seconds: the game runs as many as the frame's time holds.
inline constexpr float kStep = 1.0f / 60.0f;

// One fixed step of `dt` seconds: input to velocity, gravity, then the move in sub-steps shorter
// than half the radius, each followed by pushing the capsule's spheres out of the triangles.
StepEvents step(const Level& level, const PlayerParams& params, Player& player, const MoveInput& input, float dt = kStep);

// The point of triangle `t` nearest to `p` (Ericson, Real-Time Collision Detection 5.1.5).
glm::vec3 closestPointOnTriangle(glm::vec3 p, const Triangle& t);

}  // namespace speculum::game
