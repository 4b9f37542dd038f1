// The IBL environment against CPU evaluations of the same conventions and integrals.
#include "speculum/render/environment.hpp"
#include "speculum/core.hpp"
#include "speculum/gpu/context.hpp"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>

namespace speculum::render {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

std::filesystem::path interiorExr() {
    std::filesystem::path inRepo =
        std::filesystem::path(SPECULUM_SOURCE_DIR) / "assets/env/interior.exr";
    return std::filesystem::exists(inRepo) ? inRepo : "/work/shared/assets/env/interior.exr";
}

// Texel-centre direction of a cube face, written from the Vulkan cube face selection table
// independently of the shader's version.
glm::vec3 cubeTexelDirection(int face, int x, int y, int size) {
    float sc = 2.0f * (float(x) + 0.5f) / float(size) - 1.0f;
    float tc = 2.0f * (float(y) + 0.5f) / float(size) - 1.0f;
    const glm::vec3 dirs[6] = {{1, -tc, -sc}, {-1, -tc, sc}, {sc, 1, tc},
                               {sc, -1, -tc}, {sc, -tc, 1},  {-sc, -tc, -1}};
    return glm::normalize(dirs[face]);
}

// A smooth sky with a different colour along every axis: a flipped or swapped face shows.
EquirectImage axisSky(uint32_t width) {
    EquirectImage image{width, width / 2, {}};
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            glm::vec3 d = equirectDirection({(x + 0.5f) / width, (y + 0.5f) / image.height});
            image.texels.push_back(0.5f + 0.5f * d);
        }
    return image;
}

// Max minus min of the 2x2 texels that the bilinear lookup along dir blends.
glm::vec3 footprintRange(const EquirectImage& sky, glm::vec3 dir) {
    glm::vec2 uv = equirectUV(dir);
    int x0 = int(std::floor(uv.x * sky.width - 0.5f)),
        y0 = int(std::floor(uv.y * sky.height - 0.5f));
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            int w = int(sky.width);
            glm::vec3 t =
                sky.texel(((x0 + dx) % w + w) % w, std::clamp(y0 + dy, 0, int(sky.height) - 1));
            lo = glm::min(lo, t);
            hi = glm::max(hi, t);
        }
    return hi - lo;
}

// The split-sum (scale, bias) by midpoint quadrature over the GGX half-vector CDF and azimuth:
// the same integral as ibl_dfg.comp, evaluated on a regular grid instead of Hammersley points.
glm::vec2 dfgQuadrature(float NdotV, float roughness) {
    const double alpha = double(roughness) * roughness, a2 = alpha * alpha;
    const glm::dvec3 v(std::sqrt(1.0 - double(NdotV) * NdotV), 0.0, NdotV);
    const int n = 400;
    glm::dvec2 sum(0.0);
    for (int i = 0; i < n; ++i) {
        double u = (i + 0.5) / n;
        double cosT = std::sqrt((1.0 - u) / (1.0 + (a2 - 1.0) * u));
        double sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
        for (int j = 0; j < n; ++j) {
            double phi = 2.0 * std::numbers::pi * (j + 0.5) / n;
            glm::dvec3 h(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
            double VdotH = glm::dot(v, h);
            glm::dvec3 l = 2.0 * VdotH * h - v;
            if (l.z <= 0.0 || VdotH <= 0.0) continue;
            double NoV = NdotV, NoL = l.z;
            double vis = 0.5 / (NoL * std::sqrt(NoV * NoV * (1 - a2) + a2) +
                                NoV * std::sqrt(NoL * NoL * (1 - a2) + a2));
            double gVis = vis * 4.0 * NoL * VdotH / h.z;
            double fc = std::pow(1.0 - VdotH, 5.0);
            sum += glm::dvec2(1.0 - fc, fc) * gVis;
        }
    }
    return glm::vec2(sum / double(n * n));
}

class EnvironmentTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() { ctx_ = std::make_unique<gpu::Context>(); }
    static void TearDownTestSuite() { ctx_.reset(); }
    void TearDown() override {
        EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
        for (const std::string& m : gpu::Context::validationMessages()) ADD_FAILURE() << m;
    }
    static std::vector<float> read(const gpu::Image& image, uint32_t mip, uint32_t layer) {
        return gpu::readImageRGBA(*ctx_, image.get(), image.desc(),
                                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, mip, layer);
    }
    static std::unique_ptr<gpu::Context> ctx_;
};
std::unique_ptr<gpu::Context> EnvironmentTest::ctx_;

TEST(EnvironmentConvention, EquirectAnchorsAndRoundTrip) {
    EXPECT_NEAR(equirectUV({0, 0, -1}).x, 0.5f, 1e-6f);
    EXPECT_NEAR(equirectUV({1, 0, 0}).x, 0.75f, 1e-6f);
    EXPECT_NEAR(equirectUV({-1, 0, 0}).x, 0.25f, 1e-6f);
    EXPECT_NEAR(equirectUV({0, 1, 0}).y, 0.0f, 1e-6f);
    EXPECT_NEAR(equirectUV({0, -1, 0}).y, 1.0f, 1e-6f);
    EXPECT_NEAR(equirectUV({0, 0, -1}).y, 0.5f, 1e-6f);
    for (glm::vec2 uv : {glm::vec2(0.1f, 0.2f), glm::vec2(0.6f, 0.9f), glm::vec2(0.93f, 0.45f)}) {
        glm::vec2 back = equirectUV(equirectDirection(uv));
        EXPECT_NEAR(back.x, uv.x, 1e-5f);
        EXPECT_NEAR(back.y, uv.y, 1e-5f);
    }
}

TEST_F(EnvironmentTest, MissingFileIsBadInputNamingIt) {
    try {
        Environment env(*ctx_, "/nonexistent/sky.exr");
        FAIL() << "no exception";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("/nonexistent/sky.exr"), std::string::npos);
    }
}

TEST_F(EnvironmentTest, NonFiniteTexelsBecomeZeroWithAWarning) {
    std::filesystem::path dir(SPECULUM_TEST_TMP);
    std::filesystem::create_directories(dir);
    std::string file = (dir / "environment_nan.exr").string();
    float pixels[4 * 2 * 3];
    for (float& p : pixels) p = 0.5f;
    pixels[0] = std::nanf("");
    pixels[4] = std::numeric_limits<float>::infinity();
    auto out = OIIO::ImageOutput::create(file);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(file, OIIO::ImageSpec(4, 2, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels));
    out->close();

    int warnings = warningCount();
    EquirectImage image = loadEquirect(file);
    EXPECT_GT(warningCount(), warnings);
    EXPECT_EQ(image.texel(0, 0).r, 0.0f);
    EXPECT_EQ(image.texel(1, 0).g, 0.0f);
    EXPECT_EQ(image.texel(2, 0).b, 0.5f);
    Environment env(*ctx_, file, {.cubeSize = 8});
    for (glm::vec4 c : env.irradianceSH()) EXPECT_TRUE(std::isfinite(c.r + c.g + c.b));
}

// Mip 0 is a bilinear lookup of the sky along each texel centre (also the 256^2, 64-sample
// timing printed for the record; never asserted).
TEST_F(EnvironmentTest, CubeMip0MatchesEquirect) {
    auto start = std::chrono::steady_clock::now();
    Environment env(*ctx_, interiorExr());
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("environment build (256^2 x 6, 64 samples, incl. EXR load + SH): %.3f s\n",
                seconds);
    EquirectImage sky = loadEquirect(interiorExr());
    const int size = int(env.specular().desc().width);
    ASSERT_EQ(size, 256);
    EXPECT_EQ(env.mipCount(), 7u);
    EXPECT_EQ(env.specular().desc().width >> (env.mipCount() - 1), 4u);
    int checked = 0;
    for (int face = 0; face < 6; ++face) {
        std::vector<float> texels = read(env.specular(), 0, face);
        for (int y = face; y < size; y += 7)
            for (int x = 3 * face; x < size; x += 5) {
                glm::vec3 dir = cubeTexelDirection(face, x, y, size);
                glm::vec3 want = sky.sample(dir);
                // Float trig differs between CPU and GPU by ~1e-6 rad, which moves the bilinear
                // weights by ~1e-4 of the local contrast (the sky spans 0 to 3e4).
                glm::vec3 contrast = footprintRange(sky, dir);
                const float* got = &texels[(size_t(y) * size + x) * 4];
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(got[c], want[c],
                                1e-2f * std::abs(want[c]) + 1e-3f * contrast[c] + 1e-6f)
                        << "face " << face << " texel " << x << "," << y << " channel " << c;
                ASSERT_EQ(got[3], 1.0f);
                ++checked;
            }
    }
    EXPECT_GT(checked, 6000);
}

// A sky with 4 texels per cube texel: rows alternating 0 and 1 must average to grey in mip 0
// instead of aliasing into stripes (single bilinear lookups would give anything in 0..1).
TEST_F(EnvironmentTest, FineSkyIsAveragedIntoMip0) {
    EquirectImage sky{1024, 512, {}};
    for (uint32_t y = 0; y < sky.height; ++y)
        for (uint32_t x = 0; x < sky.width; ++x) sky.texels.emplace_back(float(y % 2));
    Environment env(*ctx_, sky, {.cubeSize = 64});
    float lo = 1.0f, hi = 0.0f;
    for (int face = 0; face < 6; ++face) {
        std::vector<float> texels = read(env.specular(), 0, face);
        for (size_t i = 0; i < texels.size(); i += 4) {
            lo = std::min(lo, texels[i]);
            hi = std::max(hi, texels[i]);
        }
    }
    EXPECT_GT(lo, 0.3f);
    EXPECT_LT(hi, 0.7f);
}

// NdotL-weighted mean of L.N over the GGX lobe with N = V = R: prefiltering the linear sky
// 0.5 + 0.5 d gives 0.5 + 0.5 k d (the tangential parts cancel by symmetry).
float lobeShrink(float alpha) {
    const int n = 256;
    double num = 0.0, den = 0.0;
    for (int i = 0; i < n; ++i) {
        double u = (i + 0.5) / n;
        double cosH = std::sqrt((1.0 - u) / (1.0 + (double(alpha) * alpha - 1.0) * u));
        double NdotL = 2.0 * cosH * cosH - 1.0;
        if (NdotL <= 0.0) continue;
        num += NdotL * NdotL;
        den += NdotL;
    }
    return float(num / den);
}

// A smooth sky prefiltered by the narrow lobes of mips 1 and 2 stays close to the sky: this
// checks that the prefilter's hardware cube lookups agree with the face table used to write
// texels (a flipped or swapped face would be off by up to 1).
TEST_F(EnvironmentTest, LowRoughnessMipsFollowTheSky) {
    Environment env(*ctx_, axisSky(256), {.cubeSize = 32});
    ASSERT_EQ(env.mipCount(), 4u);
    for (uint32_t mip = 1; mip <= 2; ++mip) {
        const int size = int(32u >> mip);
        const float roughness = float(mip) / float(env.mipCount() - 1);
        const float k = lobeShrink(roughness * roughness);
        // 64 samples and the coarse source mips that wide lobes read leave a little noise.
        const float tolerance = mip == 1 ? 0.02f : 0.04f;
        for (int face = 0; face < 6; ++face) {
            std::vector<float> texels = read(env.specular(), mip, face);
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) {
                    glm::vec3 want = 0.5f + 0.5f * k * cubeTexelDirection(face, x, y, size);
                    for (int c = 0; c < 3; ++c)
                        ASSERT_NEAR(texels[(size_t(y) * size + x) * 4 + c], want[c], tolerance)
                            << "mip " << mip << " face " << face << " texel " << x << "," << y;
                }
        }
    }
}

// A uniform sky must stay exactly uniform through every prefiltered mip (normalisation).
TEST_F(EnvironmentTest, ConstantColourIsUniformInEveryMipAndSH) {
    const glm::vec3 colour(0.25f, 0.5f, 2.0f);
    Environment env(*ctx_, colour, {.cubeSize = 64});
    EXPECT_EQ(env.mipCount(), 5u);
    for (uint32_t mip = 0; mip < env.mipCount(); ++mip)
        for (uint32_t face = 0; face < 6; ++face) {
            std::vector<float> texels = read(env.specular(), mip, face);
            for (size_t i = 0; i < texels.size(); i += 4)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(texels[i + c], colour[c], 2e-3f * colour[c])
                        << "mip " << mip << " face " << face << " texel " << i / 4;
        }
    for (glm::vec3 n :
         {glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), glm::normalize(glm::vec3(-1, -2, 3))}) {
        glm::vec3 e = evalSH(env.irradianceSH(), n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], colour[c], 1e-5f);
    }
    for (int i = 1; i < 9; ++i) EXPECT_EQ(glm::vec3(env.irradianceSH()[i]), glm::vec3(0.0f));
}

TEST_F(EnvironmentTest, DfgMatchesQuadratureAndLimits) {
    Environment env(*ctx_, glm::vec3(1.0f), {.cubeSize = 8, .dfgSize = 64});
    const int size = 64;
    std::vector<float> lut = read(env.dfg(), 0, 0);
    auto at = [&](int x, int y) {
        return glm::vec2(lut[(size_t(y) * size + x) * 4], lut[(size_t(y) * size + x) * 4 + 1]);
    };
    for (int x : {3, 20, 40, 63})
        for (int y : {2, 16, 32, 48, 63}) {
            glm::vec2 want = dfgQuadrature((x + 0.5f) / size, (y + 0.5f) / size);
            glm::vec2 got = at(x, y);
            EXPECT_NEAR(got.x, want.x, 1e-2f) << "NdotV texel " << x << " roughness texel " << y;
            EXPECT_NEAR(got.y, want.y, 1e-2f) << "NdotV texel " << x << " roughness texel " << y;
        }
    // Mirror limit: a smooth surface reflects everything, F0 * 1 + (1 - F0) * (1 - NdotV)^5 with
    // height-correlated Smith; at normal incidence scale + bias = 1 and bias = 0.
    glm::vec2 mirror = at(size - 1, 0);
    EXPECT_NEAR(mirror.x + mirror.y, 1.0f, 1e-2f);
    EXPECT_NEAR(mirror.y, 0.0f, 1e-3f);
    glm::vec2 grazing = at(8, 0);  // NdotV = 8.5 / 64
    EXPECT_NEAR(grazing.x + grazing.y, 1.0f, 1e-2f);
    EXPECT_NEAR(grazing.y, std::pow(1.0f - 8.5f / 64.0f, 5.0f), 1e-2f);
    // Rough surfaces lose energy to single scattering (the well-known 1 - E(mu) deficit).
    glm::vec2 rough = at(size - 1, size - 1);
    EXPECT_LT(rough.x + rough.y, 0.95f);
}

// Radiance max(y, 0): irradiance / pi at angle g from up is ((pi - g) cos g + sin g) * 2 / (3 pi),
// which an L2 SH reproduces to within about 0.006.
TEST_F(EnvironmentTest, SHOfHalfCosineSkyMatchesAnalyticIrradiance) {
    EquirectImage sky{512, 256, {}};
    for (uint32_t y = 0; y < sky.height; ++y)
        for (uint32_t x = 0; x < sky.width; ++x) {
            glm::vec3 d = equirectDirection({(x + 0.5f) / sky.width, (y + 0.5f) / sky.height});
            sky.texels.emplace_back(std::max(d.y, 0.0f), 2.0f * std::max(d.y, 0.0f), 0.0f);
        }
    Environment env(*ctx_, sky, {.cubeSize = 8, .intensity = 1.5f});
    const SH9& sh = env.irradianceSH();
    // Projections: Y00 -> pi * 0.282095, Y1-1 (y) -> 0.488603 * 2 pi / 3 * (2 / 3); times
    // intensity.
    EXPECT_NEAR(sh[0].r, 1.5f * kPi * 0.282095f, 3e-3f);
    EXPECT_NEAR(sh[1].r, 1.5f * 0.488603f * 2.0f * kPi / 3.0f * 2.0f / 3.0f, 3e-3f);
    for (int i : {2, 3, 4, 5, 7}) EXPECT_NEAR(sh[i].r, 0.0f, 1e-3f) << "coefficient " << i;
    for (float g = 0.0f; g <= kPi; g += 0.125f)
        for (float azimuth : {0.0f, 1.0f, 2.5f}) {
            glm::vec3 n(std::sin(g) * std::cos(azimuth), std::cos(g),
                        std::sin(g) * std::sin(azimuth));
            float exact = 1.5f * ((kPi - g) * std::cos(g) + std::sin(g)) * 2.0f / (3.0f * kPi);
            glm::vec3 e = evalSH(sh, n);
            EXPECT_NEAR(e.r, exact, 0.015f) << "angle " << g;
            EXPECT_NEAR(e.g, 2.0f * exact, 0.03f) << "angle " << g;
            EXPECT_EQ(e.b, 0.0f);
        }
}

}  // namespace
}  // namespace speculum::render
