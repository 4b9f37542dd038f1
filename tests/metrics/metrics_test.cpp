// The metrics on synthetic images whose scores are known by hand.
#include "metrics.hpp"

#include "speculum/core.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace speculum;
using metrics::Image;

namespace {

Image flat(uint32_t w, uint32_t h, glm::vec3 v) {
    return {w, h, std::vector<glm::vec3>(size_t(w) * h, v)};
}

}  // namespace

TEST(Metrics, PsnrMaeAndGrossShareOfAKnownError) {
    Image ref = flat(10, 10, glm::vec3(0.5f));
    Image test = ref;
    // 10 pixels off by 0.1 in every channel, 5 of them by 0.3 (gross) instead.
    for (int i = 0; i < 10; ++i) test.pixels[size_t(i)] += glm::vec3(i < 5 ? 0.3f : 0.1f);
    std::vector<uint8_t> all(100, 1);
    metrics::Scores s = metrics::compare(test, ref, all, 1.0f);
    double mse = (5 * 0.09 + 5 * 0.01) / 100.0;
    EXPECT_EQ(s.pixels, 100u);
    EXPECT_NEAR(*s.psnr, 10.0 * std::log10(1.0 / mse), 1e-3);
    EXPECT_NEAR(s.mae, (5 * 0.3 + 5 * 0.1) / 100.0, 1e-6);
    EXPECT_NEAR(s.grossShare, 0.05, 1e-12);
}

TEST(Metrics, OnlyMaskPixelsCount) {
    Image ref = flat(4, 1, glm::vec3(0.2f));
    Image test = ref;
    test.pixels[0] = glm::vec3(1.0f);  // outside the mask: ignored
    test.pixels[3] = glm::vec3(0.3f);
    metrics::Scores s = metrics::compare(test, ref, {0, 1, 1, 1}, 1.0f);
    EXPECT_EQ(s.pixels, 3u);
    EXPECT_NEAR(s.mae, 0.1 / 3.0, 1e-6);
    EXPECT_EQ(s.grossShare, 0.0);
    EXPECT_FALSE(metrics::compare(test, ref, {0, 0, 0, 0}, 1.0f).psnr.has_value());
}

TEST(Metrics, ClampedAfterScaling) {
    // Both saturate after the scale: no error. Without the scale they differ.
    Image ref = flat(2, 2, glm::vec3(4.0f)), test = flat(2, 2, glm::vec3(8.0f));
    std::vector<uint8_t> all(4, 1);
    EXPECT_EQ(*metrics::compare(test, ref, all, 0.5f).psnr, metrics::kMaxPsnr);
    EXPECT_NEAR(metrics::compare(test, ref, all, 0.1f).mae, 0.4, 1e-6);
    // NaN is a full error, not a silent pass.
    test.pixels[0] = glm::vec3(std::nanf(""));
    EXPECT_GT(metrics::compare(test, flat(2, 2, glm::vec3(0.0f)), all, 1.0f).grossShare, 0.0);
}

TEST(Metrics, MaskIsTheUnionOfReferenceFlagAndEngineReflection) {
    Image refMask = flat(3, 1, glm::vec3(0.0f));
    refMask.pixels[0] = glm::vec3(1.0f);
    Image engine = flat(3, 1, glm::vec3(0.0f));
    engine.pixels[2] = glm::vec3(0.0f, 0.01f, 0.0f);
    EXPECT_EQ(metrics::reflectiveMask(3, 1, &refMask, &engine), (std::vector<uint8_t>{1, 0, 1}));
    EXPECT_EQ(metrics::reflectiveMask(3, 1, nullptr, nullptr), (std::vector<uint8_t>{1, 1, 1}));
    EXPECT_THROW(metrics::reflectiveMask(4, 1, &refMask, nullptr), Error);
}

TEST(Metrics, ExcessFlickerIgnoresConstantErrorAndCountsExtraChange) {
    std::vector<Image> ref, steady, flicker;
    for (int t = 0; t < 4; ++t) {
        ref.push_back(flat(2, 2, glm::vec3(0.1f * float(t))));
        steady.push_back(flat(2, 2, glm::vec3(0.1f * float(t) + 0.2f)));         // offset, same changes
        flicker.push_back(flat(2, 2, glm::vec3(0.1f * float(t) + (t % 2 ? 0.1f : 0.0f))));  // +-0.1 extra
    }
    std::vector<std::vector<uint8_t>> masks(4, std::vector<uint8_t>(4, 1));
    EXPECT_NEAR(metrics::excessFlicker(steady, ref, masks, 1.0f), 0.0, 1e-6);
    EXPECT_NEAR(metrics::excessFlicker(flicker, ref, masks, 1.0f), 0.1, 1e-6);
    EXPECT_THROW(metrics::excessFlicker(flicker, ref, {masks[0]}, 1.0f), Error);
}

TEST(Metrics, HeatmapSaturatesAtGrossError) {
    Image ref = flat(3, 1, glm::vec3(0.5f)), test = ref;
    test.pixels[1] += glm::vec3(0.5f);
    std::vector<uint8_t> rgb = metrics::heatmap(test, ref, {1, 1, 0}, 1.0f);
    EXPECT_EQ(rgb[0] + rgb[1] + rgb[2], 0);      // no error: black
    EXPECT_EQ(rgb[3], 255);                       // gross: yellow
    EXPECT_EQ(rgb[6], rgb[7]);                    // outside the mask: grey
}

TEST(Metrics, BandMaskKeepsMaskedPixelsWithinTheBand) {
    metrics::Image band{4, 1, {{0.0f, 0, 0}, {0.1f, 0, 0}, {0.3f, 0, 0}, {0.9f, 0, 0}}};
    std::vector<uint8_t> mask{1, 1, 0, 1};
    EXPECT_EQ(metrics::bandMask(mask, band, 0.0f, 0.2f), (std::vector<uint8_t>{1, 1, 0, 0}));
    EXPECT_EQ(metrics::bandMask(mask, band, 0.2f, 1.0f), (std::vector<uint8_t>{0, 0, 0, 1}));
    EXPECT_THROW(metrics::bandMask({1, 1}, band, 0.0f, 1.0f), Error);
}

// A converged reference's unconverged pixels leave the mask and are counted; an unknown error
// (-1, one batch) and pixels outside the mask stay as they were.
TEST(Metrics, UnconvergedReferencePixelsAreLeftOut) {
    Image error{5, 1, {glm::vec3(0.0f), glm::vec3(0.02f), glm::vec3(-1.0f), glm::vec3(0.01f), glm::vec3(0.5f)}};
    size_t removed = 0;
    std::vector<uint8_t> m = metrics::convergedMask({1, 1, 1, 1, 0}, error, metrics::kMaxReferenceError, removed);
    EXPECT_EQ(m, (std::vector<uint8_t>{1, 0, 1, 1, 0}));
    EXPECT_EQ(removed, 1u);
    EXPECT_THROW(metrics::convergedMask({1, 1}, error, 0.01f, removed), Error);
}
