// CPU math of the reflections module: pyramid sizes, cell footprints (no texel lost at odd
// sizes), the CPU Hi-Z, cone angles and incircles.
#include "speculum/reflections/math.hpp"
#include "speculum/reflections/reflections.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace speculum::reflections;

TEST(ReflectionsMath, PyramidLevelsReachOneTexel) {
    EXPECT_EQ(pyramidLevels(1, 1), 1u);
    EXPECT_EQ(pyramidLevels(640, 360), 10u);
    EXPECT_EQ(pyramidLevels(317, 181), 9u);
    EXPECT_EQ(levelSize(317, 8), 1u);
    EXPECT_EQ(levelSize(181, 8), 1u);
    EXPECT_EQ(levelSize(181, 7), 1u);
    EXPECT_EQ(levelSize(360, 2), 90u);
}

TEST(ReflectionsMath, FootprintsPartitionTheFinerLevel) {
    for (uint32_t fine = 1; fine <= 65; ++fine) {
        uint32_t coarse = std::max(1u, fine / 2);
        std::vector<int> covered(fine, 0);
        for (uint32_t c = 0; c < coarse; ++c) {
            Footprint f = cellFootprint(c, fine, coarse);
            ASSERT_LE(f.last - f.first, 2u) << "fine " << fine << " cell " << c;
            for (uint32_t i = f.first; i <= f.last; ++i) covered[i]++;
        }
        for (uint32_t i = 0; i < fine; ++i) EXPECT_EQ(covered[i], 1) << "fine size " << fine << " texel " << i;
    }
}

// Every cell of every level equals the min/max over the level-0 pixels it stands for:
// [c * 2^L, (c + 1) * 2^L), the last cell of a level reaching the image edge.
TEST(ReflectionsMath, HiZCellsCoverTheirPixelRectangles) {
    for (auto [w, h] : {std::pair{317u, 181u}, std::pair{37u, 5u}, std::pair{64u, 33u}}) {
        std::mt19937 rng(w * 131 + h);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        std::vector<float> depth(size_t(w) * h);
        for (float& d : depth) d = u(rng);
        auto levels = buildHiZ(depth, w, h);
        ASSERT_EQ(levels.size(), pyramidLevels(w, h));
        for (uint32_t l = 0; l < levels.size(); ++l) {
            uint32_t lw = levelSize(w, l), lh = levelSize(h, l);
            for (uint32_t cy = 0; cy < lh; ++cy)
                for (uint32_t cx = 0; cx < lw; ++cx) {
                    uint32_t x1 = cx == lw - 1 ? w : (cx + 1) << l, y1 = cy == lh - 1 ? h : (cy + 1) << l;
                    float lo = INFINITY, hi = -INFINITY;
                    for (uint32_t y = cy << l; y < y1; ++y)
                        for (uint32_t x = cx << l; x < x1; ++x) {
                            lo = std::min(lo, depth[size_t(y) * w + x]);
                            hi = std::max(hi, depth[size_t(y) * w + x]);
                        }
                    const MinMax& m = levels[l][size_t(cy) * lw + cx];
                    ASSERT_EQ(m.farthest, lo) << w << "x" << h << " level " << l << " cell " << cx << "," << cy;
                    ASSERT_EQ(m.closest, hi) << w << "x" << h << " level " << l << " cell " << cx << "," << cy;
                }
        }
    }
}

TEST(ReflectionsMath, ConeAngleGrowsWithRoughness) {
    EXPECT_EQ(coneAngle(0.0f), 0.0f);
    // Roughness 1: alpha 1, Phong power 0, theta = acos(0.244).
    EXPECT_NEAR(coneAngle(1.0f), std::acos(0.244f), 1e-5f);
    float previous = 0.0f;
    for (float r = 0.05f; r <= 1.0f; r += 0.05f) {
        float theta = coneAngle(r);
        EXPECT_GT(theta, previous) << "roughness " << r;
        EXPECT_LT(theta, 1.5707964f);
        previous = theta;
    }
}

TEST(ReflectionsMath, IncircleOfKnownTriangles) {
    // Equilateral triangle of side a: height a sqrt(3) / 2, inradius a / (2 sqrt(3)).
    float a = 3.0f;
    EXPECT_NEAR(incircleRadius(a, a * std::sqrt(3.0f) / 2.0f), a / (2.0f * std::sqrt(3.0f)), 1e-5f);
    // Isosceles right-angled at the apex: base 2, height 1, legs sqrt(2); r = area / s.
    float s = (2.0f + 2.0f * std::sqrt(2.0f)) / 2.0f;
    EXPECT_NEAR(incircleRadius(2.0f, 1.0f), 1.0f / s, 1e-5f);
    EXPECT_NEAR(isoscelesOpposite(10.0f, std::atan(0.25f)), 5.0f, 1e-5f);
    EXPECT_EQ(incircleRadius(0.0f, 1.0f), 0.0f);
}
