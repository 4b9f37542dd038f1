// CPU twins of the module's shader math, for unit tests and tools: Hi-Z level sizes and cell
// footprints, roughness to cone angle, isosceles-triangle incircles. Each function matches the
// GLSL in modules/reflections/shaders/ line for line in what it computes.
#pragma once

#include <cstdint>
#include <vector>

namespace speculum::reflections {

// Mip count of a full pyramid over a width x height image (down to 1x1).
uint32_t pyramidLevels(uint32_t width, uint32_t height);
// Size of one dimension at `level`: max(1, floor(size / 2^level)), Vulkan's mip rule.
uint32_t levelSize(uint32_t size, uint32_t level);
// Texels [first, last] of level - 1 that cell `cell` of `level` covers along one axis: two,
// or three for the last cell when level - 1 is odd-sized, so that no texel is lost.
struct Footprint {
    uint32_t first = 0;
    uint32_t last = 0;
};
Footprint cellFootprint(uint32_t cell, uint32_t fineSize, uint32_t coarseSize);

// CPU min/max pyramid of a reversed-Z depth image: per level, x = farthest (minimum depth value),
// y = closest (maximum). Level 0 is the depth itself.
struct MinMax {
    float farthest = 0.0f;
    float closest = 0.0f;
};
std::vector<std::vector<MinMax>> buildHiZ(const std::vector<float>& depth, uint32_t width, uint32_t height);

// Cone half-angle (radians) for a perceptual roughness: alpha = r^2, the Phong power that
// matches GGX (n = 2 / alpha^2 - 2) and Uludag's theta = acos(xi^(1 / (n + 1))), xi = 0.244.
float coneAngle(float perceptualRoughness);
// Isosceles triangle of height h (the ray's screen length) and base a = 2 h tan(theta).
float isoscelesOpposite(float adjacent, float theta);
// Radius of the circle inscribed in an isosceles triangle of base a and height h.
float incircleRadius(float base, float height);

}  // namespace speculum::reflections
