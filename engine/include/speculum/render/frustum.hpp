// View-frustum culling of world-space boxes against a camera's clip volume (render.depth_prepass
// and render.gbuffer skip the draws a view cannot see). A draw costs its vertices wherever it
// lands, and a planar probe's mirrored view or a cube face sees a part of the scene only. A culled
// box has no fragment in the view, so every image is unchanged. On gallery.gltf it culls 6 of 17
// draws in the main view and 10 of 17 in the mirrored one, but the time did not move measurably
// on lavapipe (prepass + G-buffer 9.8 ms at 330x256 either way: the visible meshes carry most
// vertices, and the passes cost about 5 ms even at 96x54); it pays on scenes larger than a view.
#pragma once

#include <glm/glm.hpp>

#include <array>

namespace speculum::render {

// The clip volume's planes in world space, each with its inside where dot(plane, (p, 1)) >= 0:
// -w <= x <= w, -w <= y <= w and 0 <= z <= w (Vulkan's depth range; any projection, reversed-Z,
// infinite or oblique: a mirrored camera's near plane is the mirror's, so what lies behind it
// is culled too).
struct Frustum {
    std::array<glm::vec4, 6> planes{};
};

inline Frustum frustumOf(const glm::mat4& viewProj) {
    auto row = [&](int i) { return glm::vec4(viewProj[0][i], viewProj[1][i], viewProj[2][i], viewProj[3][i]); };
    const glm::vec4 x = row(0), y = row(1), z = row(2), w = row(3);
    return Frustum{{w + x, w - x, w + y, w - y, z, w - z}};
}

// True when the box [lo, hi] lies wholly outside one plane (conservative: a box that only
// straddles the volume's corner is kept, as a GPU would clip it).
inline bool outside(const Frustum& f, glm::vec3 lo, glm::vec3 hi) {
    for (const glm::vec4& p : f.planes) {
        // The box's corner furthest along the plane's normal.
        glm::vec3 c(p.x >= 0.0f ? hi.x : lo.x, p.y >= 0.0f ? hi.y : lo.y, p.z >= 0.0f ? hi.z : lo.z);
        if (glm::dot(glm::vec3(p), c) + p.w < 0.0f) return true;
    }
    return false;
}

// The world box of a local box [lo, hi] under `m` (Arvo's method: exact for the box's corners).
inline void transformBox(const glm::mat4& m, glm::vec3 lo, glm::vec3 hi, glm::vec3& outLo, glm::vec3& outHi) {
    outLo = outHi = glm::vec3(m[3]);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) {
            float a = m[c][r] * lo[c], b = m[c][r] * hi[c];
            outLo[r] += glm::min(a, b);
            outHi[r] += glm::max(a, b);
        }
}

}  // namespace speculum::render
