#include "player.hpp"

#include <algorithm>
#include <cmath>

namespace speculum::game {

void Level::add(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    triangles.push_back({a, b, c, glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))});
}

void Level::addBox(glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 p[8];
    for (int i = 0; i < 8; ++i) p[i] = {i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z};
    const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    for (const auto& f : faces) {
        add(p[f[0]], p[f[1]], p[f[2]]);
        add(p[f[0]], p[f[2]], p[f[3]]);
    }
}

Level levelFromScene(const Scene& scene, const std::function<bool(int node)>& solid) {
    Level level;
    for (const Instance& inst : scene.instances) {
        if (inst.mesh < 0 || (solid && !solid(inst.node))) continue;
        for (const Primitive& prim : scene.meshes[size_t(inst.mesh)].primitives) {
            auto world = [&](uint32_t i) { return glm::vec3(inst.world * glm::vec4(prim.vertices[i].position, 1.0f)); };
            for (size_t i = 0; i + 2 < prim.indices.size(); i += 3)
                level.add(world(prim.indices[i]), world(prim.indices[i + 1]), world(prim.indices[i + 2]));
        }
    }
    return level;
}

glm::vec3 closestPointOnTriangle(glm::vec3 p, const Triangle& t) {
    const glm::vec3 a = t.a, b = t.b, c = t.c;
    glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return a;
    glm::vec3 bp = p - b;
    float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) return b;
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
    glm::vec3 cp = p - c;
    float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) return c;
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    float denom = 1.0f / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

namespace {

constexpr int kSpheres = 4;

glm::vec3 sphereCentre(const PlayerParams& p, glm::vec3 feet, int i) {
    float y = p.radius + (p.height - 2.0f * p.radius) * float(i) / float(kSpheres - 1);
    return feet + glm::vec3(0.0f, y, 0.0f);
}

// Pushes the spheres out of the candidate triangles, a few rounds so that corners settle; folds
// each contact into the velocity and the events.
void resolve(const Level& level, const std::vector<uint32_t>& candidates, const PlayerParams& p, Player& player,
             StepEvents& events) {
    for (int round = 0; round < 4; ++round) {
        bool moved = false;
        for (int s = 0; s < kSpheres; ++s) {
            for (uint32_t ti : candidates) {
                const Triangle& t = level.triangles[ti];
                glm::vec3 c = sphereCentre(p, player.feet, s);
                glm::vec3 d = c - closestPointOnTriangle(c, t);
                float len2 = glm::dot(d, d);
                if (len2 >= p.radius * p.radius) continue;
                float len = std::sqrt(len2);
                glm::vec3 n;
                if (len > 1e-6f) {
                    n = d / len;
                } else {
                    n = glm::normalize(glm::cross(t.b - t.a, t.c - t.a));
                    len = 0.0f;
                }
                player.feet += n * (p.radius - len + 1e-4f);
                moved = true;
                if (n.y > p.groundSlope) {
                    player.grounded = true;
                    player.velocity.y = std::max(player.velocity.y, 0.0f);
                } else if (n.y < -p.groundSlope) {
                    events.hitCeiling = events.hitCeiling || player.velocity.y > 0.0f;
                    player.velocity.y = std::min(player.velocity.y, 0.0f);
                } else {
                    events.hitWall = true;
                    glm::vec3 h = glm::normalize(glm::vec3(n.x, 0.0f, n.z));
                    float into = glm::dot(player.velocity, h);
                    if (into < 0.0f) player.velocity -= into * h;
                }
            }
        }
        if (!moved) break;
    }
}

}  // namespace

StepEvents step(const Level& level, const PlayerParams& p, Player& player, const MoveInput& input, float dt) {
    StepEvents events;
    glm::vec3 forward(-std::sin(input.yaw), 0.0f, -std::cos(input.yaw));
    glm::vec3 right(-forward.z, 0.0f, forward.x);
    glm::vec2 move = input.move;
    if (glm::length(move) > 1.0f) move = glm::normalize(move);
    glm::vec3 walk = (forward * move.y + right * move.x) * p.walkSpeed;
    player.velocity.x = walk.x;
    player.velocity.z = walk.z;
    if (input.jump && player.grounded) player.velocity.y = p.jumpSpeed;
    player.velocity.y -= p.gravity * dt;
    bool wasGrounded = player.grounded;
    player.grounded = false;

    glm::vec3 delta = player.velocity * dt;
    // Candidates: triangles touching the capsule's bounds swept over this step.
    glm::vec3 lo = glm::min(player.feet, player.feet + delta) - glm::vec3(p.radius + 0.05f);
    glm::vec3 hi = glm::max(player.feet, player.feet + delta) + glm::vec3(p.radius + 0.05f, p.height + 0.05f, p.radius + 0.05f);
    std::vector<uint32_t> candidates;
    for (uint32_t i = 0; i < level.triangles.size(); ++i) {
        const Triangle& t = level.triangles[i];
        if (glm::all(glm::lessThanEqual(t.lo, hi)) && glm::all(glm::greaterThanEqual(t.hi, lo))) candidates.push_back(i);
    }
    int substeps = std::clamp(int(std::ceil(glm::length(delta) / (0.5f * p.radius))), 1, 16);
    for (int i = 0; i < substeps; ++i) {
        player.feet += player.velocity * (dt / float(substeps));
        resolve(level, candidates, p, player, events);
    }
    events.landed = !wasGrounded && player.grounded;
    return events;
}

}  // namespace speculum::game
