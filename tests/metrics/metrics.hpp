// Accuracy metrics of docs/design.md section 7 (measurement), written once for the accuracy tests and the bench:
// PSNR, mean absolute error and gross-error share on reflective pixels, and excess flicker
// over a camera path. Values are compared as "clamped linear": each image is multiplied by
// `scale` (the scene's exposure, so that 1 is what the display shows as white) and clamped to
// [0, 1] per channel. The definitions are in tests/reference/README.md.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace speculum::metrics {

struct Image {
    uint32_t width = 0, height = 0;
    std::vector<glm::vec3> pixels;  // row-major; one-channel files are replicated
};

// Reads an EXR (or anything OpenImageIO reads). Throws Error(ExitCode::BadInput) naming the file.
Image load(const std::filesystem::path& file);

// A pixel counts when any mask source says it is reflective: the reference's `reflective` AOV
// (> 0.5) or a non-zero pixel of the engine's `reflection` AOV (which is 0 off reflective
// pixels). Either may be absent. No source at all: every pixel counts.
std::vector<uint8_t> reflectiveMask(uint32_t width, uint32_t height, const Image* referenceMask,
                                    const Image* engineReflection);

struct Scores {
    size_t pixels = 0;          // pixels in the mask
    std::optional<double> psnr;  // dB, peak 1; absent without pixels; capped at 100 when equal
    double mae = 0.0;            // mean over pixels and channels
    double grossShare = 0.0;     // share of pixels whose largest channel error exceeds kGross
};
inline constexpr double kGross = 0.25;
// A reference pixel whose standard error (display units) is above this is not scored: two seeds'
// squared difference there would average 2 * 0.01^2 = 2e-4 (37 dB), a floor far below the
// 20-35 dB errors being measured; converged pixels sit at the reference's 0.004 target.
inline constexpr float kMaxReferenceError = 0.01f;
inline constexpr double kMaxPsnr = 100.0;

// The mask restricted to pixels whose `band` value (channel 0, e.g. the roughness AOV) lies in
// [lo, hi): per-roughness-band scores. Throws Error(ExitCode::BadInput) when the sizes differ.
std::vector<uint8_t> bandMask(const std::vector<uint8_t>& mask, const Image& band, float lo, float hi);

// The mask without the pixels where the reference is not converged: its `stderror` AOV (the
// standard error of its adaptive sampling, display units) above maxError. -1 (one batch, unknown)
// keeps the pixel. `removed` counts the mask pixels taken out. Throws Error(ExitCode::BadInput)
// when the sizes differ.
std::vector<uint8_t> convergedMask(const std::vector<uint8_t>& mask, const Image& stderror, float maxError,
                                   size_t& removed);

// A test image k times the reference's size on both axes (k a whole number), sampled where the
// reference's pixels are: both renderers shoot one ray through each pixel's centre, so for odd k
// the centre pixel of each k x k block sits exactly on the reference's sample (960x540 against
// 320x180: k = 3), and for even k the mean of the four pixels around it is the bilinear value
// there (640x360: k = 2; an edge through the block is blurred by half a test pixel). A bench at
// 960x540 is then scored against the converged 320x180 reference, never a noisier one (issue 24).
// k = 1 returns the image. Throws Error(ExitCode::BadInput) naming both sizes otherwise.
Image atReferencePixels(const Image& test, uint32_t refWidth, uint32_t refHeight);

// Throws Error(ExitCode::BadInput) when the sizes differ.
Scores compare(const Image& test, const Image& reference, const std::vector<uint8_t>& mask, float scale);

// Excess flicker: the mean over frames t >= 1 of the mean over the pixels of mask[t] and the
// channels of |(R_t - R_t-1) - (Ref_t - Ref_t-1)|, on clamped values. A sequence whose changes
// follow the reference's scores 0 whatever its constant error.
double excessFlicker(const std::vector<Image>& test, const std::vector<Image>& reference,
                     const std::vector<std::vector<uint8_t>>& masks, float scale);

// The same against a converged reference path whose `stderror` AOV is given per frame (issue 24):
// a pixel counts at frame t only where the reference is converged (stderror at most maxError) at
// t and t - 1. `referenceFloor` is what the reference's own noise adds to the score on those
// pixels: the mean of E|n_t - n_t-1| = sqrt(2 / pi) sqrt(s_t^2 + s_t-1^2) for independent
// normal errors of standard error s (the largest channel's: an upper bound), so a score far
// above it measures the engine, not the reference. `unconverged` counts the pixel-frames left out.
struct Flicker {
    double excess = 0.0, referenceFloor = 0.0;
    size_t unconverged = 0;
};
Flicker excessFlicker(const std::vector<Image>& test, const std::vector<Image>& reference,
                      const std::vector<std::vector<uint8_t>>& masks, const std::vector<Image>& stderror,
                      float maxError, float scale);

// Error heatmap, 8-bit RGB: the largest channel error on mask pixels from black through blue
// and magenta to yellow at kGross and above; other pixels show the reference in dim grey.
std::vector<uint8_t> heatmap(const Image& test, const Image& reference, const std::vector<uint8_t>& mask,
                             float scale);
void writePng(const std::filesystem::path& file, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb);

}  // namespace speculum::metrics
