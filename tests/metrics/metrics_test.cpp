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

// A 3x test image scored at the reference's pixels takes each 3x3 block's centre pixel (the same
// ray as the reference's); a 2x image the mean of the four pixels around the centre; other sizes
// are an error naming both.
TEST(Metrics, TestImagesAreSampledAtTheReferencesPixelCentres) {
    Image three{6, 3, {}};
    for (uint32_t i = 0; i < 18; ++i) three.pixels.push_back(glm::vec3(float(i)));
    Image a = metrics::atReferencePixels(three, 2, 1);
    ASSERT_EQ(a.pixels.size(), 2u);
    EXPECT_EQ(a.pixels[0].x, 7.0f);   // row 1, column 1
    EXPECT_EQ(a.pixels[1].x, 10.0f);  // row 1, column 4
    Image two{4, 2, {}};
    for (uint32_t i = 0; i < 8; ++i) two.pixels.push_back(glm::vec3(float(i)));
    Image b = metrics::atReferencePixels(two, 2, 1);
    EXPECT_FLOAT_EQ(b.pixels[0].x, (0 + 1 + 4 + 5) / 4.0f);
    EXPECT_FLOAT_EQ(b.pixels[1].x, (2 + 3 + 6 + 7) / 4.0f);
    EXPECT_EQ(metrics::atReferencePixels(two, 4, 2).pixels, two.pixels);
    EXPECT_THROW(metrics::atReferencePixels(two, 3, 1), Error);   // 4 is not a multiple of 3
    EXPECT_THROW(metrics::atReferencePixels(three, 2, 2), Error);  // 3x on x, 1.5x on y
}

// Against a converged path: a pixel unconverged at t or t - 1 leaves the score and is counted, and
// the reference's own floor is sqrt(2 / pi) sqrt(s_t^2 + s_t-1^2) averaged over what is scored.
TEST(Metrics, FlickerAgainstAConvergedPathLeavesUnconvergedPixelsOutAndReportsTheFloor) {
    std::vector<Image> ref, test, err;
    for (int t = 0; t < 3; ++t) {
        ref.push_back(flat(2, 1, glm::vec3(0.0f)));
        test.push_back(flat(2, 1, glm::vec3(t % 2 ? 0.1f : 0.0f)));
        err.push_back(flat(2, 1, glm::vec3(0.003f)));
    }
    test[1].pixels[1] = glm::vec3(0.9f);  // the unconverged pixel's flicker must not count
    err[1].pixels[1] = glm::vec3(0.05f);
    std::vector<std::vector<uint8_t>> masks(3, std::vector<uint8_t>(2, 1));
    metrics::Flicker f = metrics::excessFlicker(test, ref, masks, err, metrics::kMaxReferenceError, 1.0f);
    EXPECT_NEAR(f.excess, 0.1, 1e-6);
    EXPECT_EQ(f.unconverged, 2u);  // pixel 1 at t = 1 and t = 2 (its t - 1)
    EXPECT_NEAR(f.referenceFloor, std::sqrt(2.0 / 3.14159265) * std::sqrt(2.0) * 0.003, 1e-6);
    // Without the errors the same sequences score the outlier too.
    EXPECT_GT(metrics::excessFlicker(test, ref, masks, 1.0f), 0.3);
}
