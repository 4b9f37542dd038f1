#include "metrics.hpp"

#include "speculum/core.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

namespace speculum::metrics {
namespace {

glm::vec3 clamped(glm::vec3 v, float scale) {
    glm::vec3 c = v * scale;
    for (int i = 0; i < 3; ++i)
        c[i] = std::isfinite(c[i]) ? std::clamp(c[i], 0.0f, 1.0f) : 1.0f;  // NaN and Inf count as full error
    return c;
}

void checkSizes(const Image& a, const Image& b, const char* what) {
    if (a.width != b.width || a.height != b.height)
        throw Error(ExitCode::BadInput, std::string(what) + ": image sizes differ (" + std::to_string(a.width) + "x" +
                                            std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                            std::to_string(b.height) + ")");
}

}  // namespace

Image load(const std::filesystem::path& file) {
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) throw inputError(file.string(), "cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    int channels = std::min(spec.nchannels, 3);
    if (spec.width <= 0 || spec.height <= 0 || channels <= 0) throw inputError(file.string(), "image has no pixels");
    std::vector<float> px(size_t(spec.width) * spec.height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, px.data()))
        throw inputError(file.string(), "cannot decode image: " + in->geterror());
    Image img{uint32_t(spec.width), uint32_t(spec.height), {}};
    img.pixels.resize(size_t(spec.width) * spec.height);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) img.pixels[i][c] = px[i * channels + size_t(std::min(c, channels - 1))];
    return img;
}

std::vector<uint8_t> reflectiveMask(uint32_t width, uint32_t height, const Image* referenceMask,
                                    const Image* engineReflection) {
    size_t n = size_t(width) * height;
    if (!referenceMask && !engineReflection) return std::vector<uint8_t>(n, 1);
    std::vector<uint8_t> mask(n, 0);
    Image size{width, height, {}};
    if (referenceMask) {
        checkSizes(*referenceMask, size, "reference mask");
        for (size_t i = 0; i < n; ++i) mask[i] |= referenceMask->pixels[i].x > 0.5f;
    }
    if (engineReflection) {
        checkSizes(*engineReflection, size, "engine reflection");
        for (size_t i = 0; i < n; ++i) mask[i] |= engineReflection->pixels[i] != glm::vec3(0.0f);
    }
    return mask;
}

std::vector<uint8_t> bandMask(const std::vector<uint8_t>& mask, const Image& band, float lo, float hi) {
    if (mask.size() != band.pixels.size()) throw Error(ExitCode::BadInput, "bands: the band image's size differs");
    std::vector<uint8_t> out(mask.size());
    for (size_t i = 0; i < mask.size(); ++i) {
        float v = band.pixels[i].x;
        out[i] = mask[i] && v >= lo && v < hi;
    }
    return out;
}

std::vector<uint8_t> convergedMask(const std::vector<uint8_t>& mask, const Image& stderror, float maxError,
                                   size_t& removed) {
    if (mask.size() != stderror.pixels.size())
        throw Error(ExitCode::BadInput, "converged: the reference error image's size differs");
    std::vector<uint8_t> out(mask);
    for (size_t i = 0; i < mask.size(); ++i)
        if (mask[i] && stderror.pixels[i].x > maxError) {
            out[i] = 0;
            ++removed;
        }
    return out;
}

Image atReferencePixels(const Image& test, uint32_t refWidth, uint32_t refHeight) {
    uint32_t k = refWidth ? test.width / refWidth : 0;
    if (k == 0 || refHeight == 0 || test.width != k * refWidth || test.height != k * refHeight)
        throw Error(ExitCode::BadInput, "at reference pixels: the test image (" + std::to_string(test.width) + "x" +
                                            std::to_string(test.height) + ") is not a whole multiple of the reference (" +
                                            std::to_string(refWidth) + "x" + std::to_string(refHeight) + ")");
    if (k == 1) return test;
    Image out{refWidth, refHeight, std::vector<glm::vec3>(size_t(refWidth) * refHeight)};
    auto at = [&](uint32_t x, uint32_t y) { return test.pixels[size_t(y) * test.width + x]; };
    for (uint32_t y = 0; y < refHeight; ++y)
        for (uint32_t x = 0; x < refWidth; ++x) {
            // The reference pixel's centre is at test pixel coordinates k x + k / 2.
            uint32_t cx = x * k + k / 2, cy = y * k + k / 2;
            out.pixels[size_t(y) * refWidth + x] =
                k % 2 ? at(cx, cy) : 0.25f * (at(cx - 1, cy - 1) + at(cx, cy - 1) + at(cx - 1, cy) + at(cx, cy));
        }
    return out;
}

Scores compare(const Image& test, const Image& reference, const std::vector<uint8_t>& mask, float scale) {
    checkSizes(test, reference, "compare");
    if (mask.size() != test.pixels.size()) throw Error(ExitCode::BadInput, "compare: mask size differs from the images");
    Scores s;
    double se = 0.0, ae = 0.0;
    size_t gross = 0;
    for (size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        glm::vec3 d = glm::abs(clamped(test.pixels[i], scale) - clamped(reference.pixels[i], scale));
        se += double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z;
        ae += double(d.x) + d.y + d.z;
        gross += std::max({d.x, d.y, d.z}) > kGross;
        ++s.pixels;
    }
    if (s.pixels == 0) return s;
    double mse = se / double(s.pixels * 3);
    s.psnr = mse > 0.0 ? std::min(kMaxPsnr, 10.0 * std::log10(1.0 / mse)) : kMaxPsnr;
    s.mae = ae / double(s.pixels * 3);
    s.grossShare = double(gross) / double(s.pixels);
    return s;
}

double excessFlicker(const std::vector<Image>& test, const std::vector<Image>& reference,
                     const std::vector<std::vector<uint8_t>>& masks, float scale) {
    return excessFlicker(test, reference, masks, {}, 0.0f, scale).excess;
}

Flicker excessFlicker(const std::vector<Image>& test, const std::vector<Image>& reference,
                      const std::vector<std::vector<uint8_t>>& masks, const std::vector<Image>& stderror,
                      float maxError, float scale) {
    if (test.size() != reference.size() || masks.size() != test.size() ||
        (!stderror.empty() && stderror.size() != test.size()))
        throw Error(ExitCode::BadInput, "flicker: the sequences have different frame counts");
    const double kMeanAbsOfUnitNormal = std::sqrt(2.0 / 3.14159265358979323846);
    Flicker f;
    double sum = 0.0, floorSum = 0.0;
    size_t frames = 0;
    for (size_t t = 1; t < test.size(); ++t) {
        checkSizes(test[t], reference[t], "flicker");
        checkSizes(test[t - 1], test[t], "flicker");
        checkSizes(reference[t - 1], reference[t], "flicker");
        if (!stderror.empty()) checkSizes(stderror[t], reference[t], "flicker (reference error)");
        double frameSum = 0.0, frameFloor = 0.0;
        size_t pixels = 0;
        for (size_t i = 0; i < masks[t].size(); ++i) {
            if (!masks[t][i]) continue;
            if (!stderror.empty()) {
                // -1: one batch, unknown; counted as converged with no noise, as compare() keeps it.
                float a = std::max(stderror[t].pixels[i].x, 0.0f), b = std::max(stderror[t - 1].pixels[i].x, 0.0f);
                if (a > maxError || b > maxError) {
                    ++f.unconverged;
                    continue;
                }
                frameFloor += kMeanAbsOfUnitNormal * std::sqrt(double(a) * a + double(b) * b);
            }
            glm::vec3 dt = clamped(test[t].pixels[i], scale) - clamped(test[t - 1].pixels[i], scale);
            glm::vec3 dr = clamped(reference[t].pixels[i], scale) - clamped(reference[t - 1].pixels[i], scale);
            glm::vec3 e = glm::abs(dt - dr);
            frameSum += double(e.x) + e.y + e.z;
            ++pixels;
        }
        // A frame without reflective pixels has nothing to flicker.
        if (pixels == 0) continue;
        sum += frameSum / double(pixels * 3);
        floorSum += frameFloor / double(pixels);
        ++frames;
    }
    if (frames) {
        f.excess = sum / double(frames);
        f.referenceFloor = floorSum / double(frames);
    }
    return f;
}

std::vector<uint8_t> heatmap(const Image& test, const Image& reference, const std::vector<uint8_t>& mask,
                             float scale) {
    checkSizes(test, reference, "heatmap");
    // Black, blue, magenta, yellow: error 0, kGross / 3, 2 kGross / 3, kGross.
    const glm::vec3 ramp[4] = {{0, 0, 0}, {0.1f, 0.2f, 1.0f}, {0.9f, 0.1f, 0.8f}, {1.0f, 0.95f, 0.2f}};
    std::vector<uint8_t> rgb(test.pixels.size() * 3);
    for (size_t i = 0; i < test.pixels.size(); ++i) {
        glm::vec3 c;
        glm::vec3 ref = clamped(reference.pixels[i], scale);
        if (mask[i]) {
            glm::vec3 d = glm::abs(clamped(test.pixels[i], scale) - ref);
            float x = std::min(std::max({d.x, d.y, d.z}) / float(kGross), 1.0f) * 3.0f;
            int k = std::min(int(x), 2);
            c = glm::mix(ramp[k], ramp[k + 1], x - float(k));
        } else {
            c = glm::vec3(0.25f * glm::dot(ref, glm::vec3(0.2126f, 0.7152f, 0.0722f)));
        }
        for (int ch = 0; ch < 3; ++ch) rgb[i * 3 + size_t(ch)] = uint8_t(std::lround(std::clamp(c[ch], 0.0f, 1.0f) * 255.0f));
    }
    return rgb;
}

void writePng(const std::filesystem::path& file, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb) {
    auto out = OIIO::ImageOutput::create(file.string());
    OIIO::ImageSpec spec(int(width), int(height), 3, OIIO::TypeDesc::UINT8);
    if (!out || !out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) || !out->close())
        throw Error(ExitCode::Failure, file.string() + ": cannot write the heatmap");
}

}  // namespace speculum::metrics
