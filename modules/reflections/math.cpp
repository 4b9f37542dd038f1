#include "speculum/reflections/math.hpp"

#include <algorithm>
#include <cmath>

namespace speculum::reflections {

uint32_t pyramidLevels(uint32_t width, uint32_t height) {
    uint32_t levels = 1;
    for (uint32_t m = std::max(width, height); m > 1; m /= 2) ++levels;
    return levels;
}

uint32_t levelSize(uint32_t size, uint32_t level) {
    return std::max(1u, size >> level);
}

Footprint cellFootprint(uint32_t cell, uint32_t fineSize, uint32_t coarseSize) {
    Footprint f{cell * 2, std::min(cell * 2 + 1, fineSize - 1)};
    if (cell == coarseSize - 1) f.last = fineSize - 1;
    return f;
}

std::vector<std::vector<MinMax>> buildHiZ(const std::vector<float>& depth, uint32_t width, uint32_t height) {
    std::vector<std::vector<MinMax>> levels;
    std::vector<MinMax> base(depth.size());
    for (size_t i = 0; i < depth.size(); ++i) base[i] = {depth[i], depth[i]};
    levels.push_back(std::move(base));
    uint32_t n = pyramidLevels(width, height);
    for (uint32_t l = 1; l < n; ++l) {
        uint32_t fw = levelSize(width, l - 1), fh = levelSize(height, l - 1);
        uint32_t cw = levelSize(width, l), ch = levelSize(height, l);
        const std::vector<MinMax>& fine = levels.back();
        std::vector<MinMax> coarse(size_t(cw) * ch);
        for (uint32_t y = 0; y < ch; ++y)
            for (uint32_t x = 0; x < cw; ++x) {
                Footprint fx = cellFootprint(x, fw, cw), fy = cellFootprint(y, fh, ch);
                MinMax m{INFINITY, -INFINITY};
                for (uint32_t j = fy.first; j <= fy.last; ++j)
                    for (uint32_t i = fx.first; i <= fx.last; ++i) {
                        const MinMax& v = fine[size_t(j) * fw + i];
                        m.farthest = std::min(m.farthest, v.farthest);
                        m.closest = std::max(m.closest, v.closest);
                    }
                coarse[size_t(y) * cw + x] = m;
            }
        levels.push_back(std::move(coarse));
    }
    return levels;
}

float coneAngle(float perceptualRoughness) {
    float r = std::clamp(perceptualRoughness, 0.0f, 1.0f);
    float alpha = std::max(r * r, 1e-4f);
    float power = 2.0f / (alpha * alpha) - 2.0f;
    // A power of 2^20 is a mirror to the pixel at any screen size we render.
    if (power > 1048576.0f) return 0.0f;
    return std::acos(std::pow(0.244f, 1.0f / (power + 1.0f)));
}

float isoscelesOpposite(float adjacent, float theta) {
    return 2.0f * std::tan(theta) * adjacent;
}

float incircleRadius(float base, float height) {
    if (height <= 0.0f || base <= 0.0f) return 0.0f;
    return base * (std::sqrt(base * base + 4.0f * height * height) - base) / (4.0f * height);
}

}  // namespace speculum::reflections
