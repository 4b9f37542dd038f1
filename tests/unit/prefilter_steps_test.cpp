// The time-sliced prefilter's plan (render::planPrefilterSteps): every texel of every target mip
// is written by exactly one slice, slices never leave their mip's face, and a step stays within
// its budget unless one minimal slice (eight rows of one face) is already over it.
#include "speculum/render/cube_filter.hpp"

#include <gtest/gtest.h>

#include <algorithm>

using speculum::render::planPrefilterSteps;
using speculum::render::PrefilterSlice;

namespace {

void expectExactCover(uint32_t size, uint32_t mips, uint32_t firstMip, uint32_t samples, uint64_t budget) {
    SCOPED_TRACE("size " + std::to_string(size) + " budget " + std::to_string(budget));
    auto steps = planPrefilterSteps(size, mips, firstMip, samples, budget);
    std::vector<std::vector<int>> hits(mips);
    for (uint32_t m = 0; m < mips; ++m) hits[m].assign(size_t(std::max(1u, size >> m)) * std::max(1u, size >> m) * 6, 0);
    uint64_t total = 0;
    uint32_t lastMip = firstMip;
    for (const auto& step : steps) {
        ASSERT_FALSE(step.empty());
        uint64_t work = 0;
        for (const PrefilterSlice& s : step) {
            const uint32_t n = std::max(1u, size >> s.mip);
            ASSERT_GE(s.mip, firstMip);
            ASSERT_LT(s.mip, mips);
            EXPECT_GE(s.mip, lastMip) << "mips in order";
            lastMip = s.mip;
            ASSERT_LE(s.firstFace + s.faces, 6u);
            ASSERT_LE(s.firstRow + s.rows, n);
            // A dispatch covers rows in workgroups of eight: a slice that stops short of the face's
            // end would overwrite the next one's rows.
            if (s.firstRow + s.rows < n) {
                EXPECT_EQ(s.rows % 8, 0u);
            }
            for (uint32_t f = s.firstFace; f < s.firstFace + s.faces; ++f)
                for (uint32_t y = s.firstRow; y < s.firstRow + s.rows; ++y)
                    for (uint32_t x = 0; x < n; ++x) ++hits[s.mip][(size_t(f) * n + y) * n + x];
            EXPECT_EQ(s.work, uint64_t(n) * s.rows * s.faces * (s.mip == 0 ? 1 : samples));
            work += s.work;
        }
        total += work;
        // Over budget only as one minimal slice: eight rows (or the face) of one face.
        if (work > budget) {
            ASSERT_EQ(step.size(), 1u);
            EXPECT_EQ(step[0].faces, 1u);
            EXPECT_LE(step[0].rows, 8u);
        }
    }
    for (uint32_t m = 0; m < mips; ++m)
        for (size_t i = 0; i < hits[m].size(); ++i) {
            ASSERT_EQ(hits[m][i], m < firstMip ? 0 : 1) << "mip " << m << " texel " << i;
        }
    uint64_t expected = 0;
    for (uint32_t m = firstMip; m < mips; ++m) {
        uint64_t n = std::max(1u, size >> m);
        expected += n * n * 6 * (m == 0 ? 1 : samples);
    }
    EXPECT_EQ(total, expected);
}

}  // namespace

TEST(PrefilterSteps, EveryTexelOnceAtAnyBudget) {
    for (uint64_t budget : {uint64_t(1), uint64_t(1000), uint64_t(1) << 19, uint64_t(3) << 20, uint64_t(1) << 40})
        expectExactCover(256, 7, 0, 64, budget);
    expectExactCover(64, 5, 0, 64, 1 << 16);
    expectExactCover(128, 6, 1, 32, 1 << 18);
    expectExactCover(8, 2, 0, 1, 10);
}

TEST(PrefilterSteps, AnUnlimitedBudgetIsOneStepOfWholeMips) {
    auto steps = planPrefilterSteps(256, 7, 0, 64, ~uint64_t(0));
    ASSERT_EQ(steps.size(), 1u);
    ASSERT_EQ(steps[0].size(), 7u);
    for (uint32_t m = 0; m < 7; ++m) {
        EXPECT_EQ(steps[0][m].mip, m);
        EXPECT_EQ(steps[0][m].faces, 6u);
        EXPECT_EQ(steps[0][m].rows, 256u >> m);
    }
}

TEST(PrefilterSteps, StepsAreNearlyEven) {
    // 256^2, 64 samples: about 8.4 M texel-samples in steps of 512 k. The budget is met and no
    // step but the last is below half of it (packing fills steps).
    const uint64_t budget = uint64_t(1) << 19;
    auto steps = planPrefilterSteps(256, 7, 0, 64, budget);
    EXPECT_GE(steps.size(), 16u);
    EXPECT_LE(steps.size(), 24u);
    for (size_t i = 0; i + 1 < steps.size(); ++i) {
        uint64_t work = 0;
        for (const PrefilterSlice& s : steps[i]) work += s.work;
        EXPECT_LE(work, budget) << "step " << i;
        EXPECT_GE(work, budget / 2) << "step " << i;
    }
}
