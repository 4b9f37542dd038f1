// Image-based lighting: equirect sky -> prefiltered specular cube, DFG table, irradiance SH.
//
// Conventions (the reflection module and the Embree reference renderer copy these; the C++
// functions equirectUV / EquirectImage::sample / evalSH in environment.hpp are the reference):
//
//   Sky: world space is Y up. A unit direction d maps to
//     u = 0.5 + atan2(d.x, -d.z) / (2 pi),  v = acos(clamp(d.y, -1, 1)) / pi,
//   v = 0 at the top row; texel (i, j) is centred at ((i + 0.5) / W, (j + 0.5) / H); lookups are
//   bilinear, wrapping in u and clamping in v. Radiance = file RGB * EnvironmentOptions::intensity.
//
//   Specular cube: faces +X, -X, +Y, -Y, +Z, -Z as in the Vulkan cube face selection table, so
//   texture(samplerCube, d) is the radiance seen along d. Mip m (of mipCount, the last 4x4) is the
//   GGX prefilter (N = V = R) for perceptual roughness m / (mipCount - 1), alpha = roughness^2.
//
//   DFG: RG16F, texel (i, j) holds (scale, bias) for N.V = (i + 0.5) / size and perceptual
//   roughness (j + 0.5) / size; specular = prefiltered * (F0 * scale + bias).
//
//   SH: L2 real basis, order Y00, Y1-1, Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22 with constants
//   0.282095, 0.488603 (y, z, x), 1.092548 (xy, yz), 0.315392 (3z^2 - 1), 1.092548 (xz),
//   0.546274 (x^2 - y^2); coefficients scaled by A_l / pi (1, 2/3, 1/4) so evalSH(n) = E(n) / pi.
//   shaders/common/sh.glsl evaluates the same basis.
//
// GPU build (one submit): the equirect goes up as a storage buffer; ibl_equirect_to_cube writes
// mip 0 of both a temporary radiance cube and the specular cube (a bilinear lookup at the texel
// centre, or the mean of n x n lookups when the sky has n > 1 texels per cube texel);
// ibl_downsample box-filters the radiance cube down to 1x1; ibl_prefilter reads that chain with
// filtered importance sampling to write the specular mips 1..N-1; ibl_dfg fills the table.
#include "speculum/render/environment.hpp"

#include "speculum/core.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/render/cube_filter.hpp"
#include "speculum/scene.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>

namespace speculum::render {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr uint32_t kDfgSamples = 1024;
constexpr uint32_t kGroup = 8;  // local size of every ibl_*.comp

uint32_t groups(uint32_t n) {
    return (n + kGroup - 1) / kGroup;
}

void validate(const EnvironmentOptions& o) {
    if (o.cubeSize < 8 || !std::has_single_bit(o.cubeSize))
        throw argumentError("environment cube size must be a power of two >= 8, got " +
                            std::to_string(o.cubeSize));
    if (o.prefilterSamples == 0) throw argumentError("environment prefilter samples must be >= 1");
    if (o.dfgSize == 0) throw argumentError("environment DFG size must be >= 1");
    if (!(o.intensity >= 0.0f) || !std::isfinite(o.intensity))
        throw argumentError("environment intensity must be finite and >= 0");
}

// The nine basis functions, in the documented order.
std::array<float, 9> shBasis(glm::vec3 n) {
    return {0.282095f,
            0.488603f * n.y,
            0.488603f * n.z,
            0.488603f * n.x,
            1.092548f * n.x * n.y,
            1.092548f * n.y * n.z,
            0.315392f * (3.0f * n.z * n.z - 1.0f),
            1.092548f * n.x * n.z,
            0.546274f * (n.x * n.x - n.y * n.y)};
}

constexpr std::array<float, 9> kCosineLobe = {1.0f,  2.0f / 3.0f, 2.0f / 3.0f, 2.0f / 3.0f, 0.25f,
                                              0.25f, 0.25f,       0.25f,       0.25f};

}  // namespace

glm::vec2 equirectUV(glm::vec3 dir) {
    glm::vec3 d = glm::normalize(dir);
    return {0.5f + std::atan2(d.x, -d.z) / (2.0f * kPi),
            std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi};
}

glm::vec3 equirectDirection(glm::vec2 uv) {
    float phi = (uv.x - 0.5f) * 2.0f * kPi;
    float theta = uv.y * kPi;
    float s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

glm::vec3 EquirectImage::sample(glm::vec3 dir) const {
    glm::vec2 uv = equirectUV(dir);
    float px = uv.x * float(width) - 0.5f;
    float py = uv.y * float(height) - 0.5f;
    float x0 = std::floor(px), y0 = std::floor(py);
    float fx = px - x0, fy = py - y0;
    int w = int(width), h = int(height);
    auto at = [&](int x, int y) { return texel(((x % w) + w) % w, std::clamp(y, 0, h - 1)); };
    int x = int(x0), y = int(y0);
    glm::vec3 top = glm::mix(at(x, y), at(x + 1, y), fx);
    glm::vec3 bottom = glm::mix(at(x, y + 1), at(x + 1, y + 1), fx);
    return glm::mix(top, bottom, fy);
}

EquirectImage loadEquirect(const std::filesystem::path& path) {
    const std::string file = path.string();
    checkEnvironmentImage(path);  // regular file and header limits before any pixel is read
    auto in = OIIO::ImageInput::open(file);
    if (!in) throw inputError(file, "cannot read environment map: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw inputError(file, "environment map has no pixels");
    EquirectImage image;
    image.width = uint32_t(spec.width);
    image.height = uint32_t(spec.height);
    int channels = spec.nchannels >= 3 ? 3 : 1;  // grey (+ alpha) is replicated below
    std::vector<float> pixels(size_t(spec.width) * spec.height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data())) {
        std::string why = in->geterror();  // empty for some truncated files (issue 15)
        throw inputError(file, "cannot decode environment map: " +
                                   (why.empty() ? std::string("its pixels are truncated or corrupt") : why));
    }
    in->close();

    image.texels.resize(size_t(image.width) * image.height);
    size_t nonFinite = 0, negative = 0;
    for (size_t i = 0; i < image.texels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            float v = pixels[i * channels + (channels == 3 ? c : 0)];
            // NaN/inf would poison every filtered mip and SH coefficient they touch.
            if (!std::isfinite(v)) {
                v = 0.0f;
                ++nonFinite;
            } else if (v < 0.0f) {  // lossy EXR compression (DWA) leaves tiny negatives: harmless
                v = 0.0f;
                ++negative;
            }
            image.texels[i][c] = v;
        }
    }
    if (nonFinite > 0)
        logWarning(file + ": " + std::to_string(nonFinite) + " non-finite values set to 0");
    if (negative > 0)
        log(LogLevel::Debug, file + ": " + std::to_string(negative) + " negative values set to 0");
    return image;
}

SH9 projectIrradianceSH(const EquirectImage& image) {
    std::array<glm::dvec3, 9> acc{};
    const double dPhi = 2.0 * std::numbers::pi / image.width;
    for (uint32_t y = 0; y < image.height; ++y) {
        // Exact solid angle of the row's texels, so a constant sky integrates to exactly 4 pi.
        double theta0 = std::numbers::pi * y / image.height;
        double theta1 = std::numbers::pi * (y + 1) / image.height;
        double dOmega = dPhi * (std::cos(theta0) - std::cos(theta1));
        float v = (float(y) + 0.5f) / float(image.height);
        for (uint32_t x = 0; x < image.width; ++x) {
            glm::vec3 d = equirectDirection({(float(x) + 0.5f) / float(image.width), v});
            std::array<float, 9> basis = shBasis(d);
            glm::dvec3 radiance = glm::dvec3(image.texel(int(x), int(y))) * dOmega;
            for (int i = 0; i < 9; ++i) acc[i] += radiance * double(basis[i]);
        }
    }
    SH9 sh{};
    for (int i = 0; i < 9; ++i) sh[i] = glm::vec4(glm::vec3(acc[i] * double(kCosineLobe[i])), 0.0f);
    return sh;
}

glm::vec3 evalSH(const SH9& sh, glm::vec3 n) {
    std::array<float, 9> basis = shBasis(n);
    glm::vec3 r(0.0f);
    for (int i = 0; i < 9; ++i) r += glm::vec3(sh[i]) * basis[i];
    return glm::max(r, glm::vec3(0.0f));  // as sh.glsl: ringing must not make light negative
}

namespace {

// Push constants; layouts mirror the shaders' push_constant blocks.
struct CubePush {
    uint32_t width, height, cubeSize;
    float scale;
    uint32_t supersample;
};
struct DfgPush {
    uint32_t size, samples;
};

constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;

struct IblPipelines {
    gpu::Pipeline cube, dfg;
    CubeFilter filter;

    explicit IblPipelines(const gpu::Context& ctx)
        : cube(gpu::createComputePipeline(ctx, "engine/ibl_equirect_to_cube.comp", sizeof(CubePush),
                                          "render.environment.equirect_to_cube")),
          dfg(gpu::createComputePipeline(ctx, "engine/ibl_dfg.comp", sizeof(DfgPush), "render.environment.dfg")),
          filter(ctx) {}
};

template <class T>
void push(VkCommandBuffer cmd, const gpu::Pipeline& pipeline, const T& constants) {
    vkCmdPushConstants(cmd, pipeline.layout(), kCompute, 0, sizeof(T), &constants);
}

void toReadOnly(VkCommandBuffer cmd, const gpu::Image& image, uint32_t baseMip, uint32_t mips) {
    gpu::transition(cmd, image.get(), image.aspect(), VK_IMAGE_LAYOUT_GENERAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, baseMip, mips);
}

// Everything the recorded build reads; kept alive by build() until the submit has finished.
struct BuildInputs {
    const gpu::Buffer& equirect;
    uint32_t equirectWidth, equirectHeight;
    float scale;
    const gpu::Image& radiance;  // temporary: box mip chain down to 1x1
    VkSampler sampler;
    uint32_t samples;
};

void recordCubeChain(const gpu::Context& ctx, VkCommandBuffer cmd, const IblPipelines& p,
                     const BuildInputs& in, const gpu::Image& specular) {
    const uint32_t size = specular.desc().width;
    p.cube.bind(cmd);
    gpu::DescriptorWriter()
        .buffer("equirect", in.equirect.get())
        .storage("radianceCube", in.radiance.mipView(0))
        .storage("specularCube", specular.mipView(0))
        .push(ctx, cmd, p.cube);
    // A face spans a quarter of the equirect's width; beyond one sky texel per cube texel the
    // lookups are averaged (capped: 8 x 8 keeps a 16k sky at cube size 512 cheap enough).
    const uint32_t supersample = std::clamp((in.equirectWidth + 4 * size - 1) / (4 * size), 1u, 8u);
    push(cmd, p.cube, CubePush{in.equirectWidth, in.equirectHeight, size, in.scale, supersample});
    vkCmdDispatch(cmd, groups(size), groups(size), 6);
    p.filter.recordBoxChain(cmd, in.radiance, in.sampler);
}

void recordPrefilter(VkCommandBuffer cmd, const IblPipelines& p, const BuildInputs& in,
                     const gpu::Image& specular) {
    std::vector<VkImageView> views;
    for (uint32_t m = 0; m < specular.desc().mips; ++m) views.push_back(specular.mipView(m));
    p.filter.recordPrefilter(cmd, in.radiance, in.sampler, views, specular.desc().width, 1, in.samples);
}

void recordDfg(const gpu::Context& ctx, VkCommandBuffer cmd, const IblPipelines& p,
               const gpu::Image& dfg) {
    const uint32_t size = dfg.desc().width;
    p.dfg.bind(cmd);
    gpu::DescriptorWriter().storage("dfg", dfg.mipView(0)).push(ctx, cmd, p.dfg);
    push(cmd, p.dfg, DfgPush{size, kDfgSamples});
    vkCmdDispatch(cmd, groups(size), groups(size), 1);
}

gpu::Buffer uploadEquirect(const gpu::Context& ctx, const EquirectImage& image) {
    std::vector<float> rgb;
    rgb.reserve(image.texels.size() * 3);
    for (glm::vec3 t : image.texels) rgb.insert(rgb.end(), {t.r, t.g, t.b});
    return gpu::uploadBuffer(ctx, std::as_bytes(std::span<const float>(rgb)),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "render.environment.equirect");
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

Environment::Environment(const gpu::Context& ctx, const std::filesystem::path& equirectExr,
                         const EnvironmentOptions& options) {
    validate(options);
    auto start = std::chrono::steady_clock::now();
    EquirectImage image = loadEquirect(equirectExr);
    sh_ = projectIrradianceSH(image);
    for (glm::vec4& c : sh_) c *= options.intensity;
    build(ctx, image, options, equirectExr.string());
    double seconds = secondsSince(start);
    // Only slow builds are worth a line: the fast path must not clutter every test's output.
    log(seconds > 1.0 ? LogLevel::Info : LogLevel::Debug,
        "environment " + equirectExr.string() + " (" + std::to_string(image.width) + "x" +
            std::to_string(image.height) + ") built in " + std::to_string(seconds) + " s");
}

Environment::Environment(const gpu::Context& ctx, glm::vec3 constantRadiance,
                         const EnvironmentOptions& options) {
    validate(options);
    glm::vec3 c = constantRadiance * options.intensity;
    // Exact rather than integrated: evalSH then returns c everywhere (E = pi c for a uniform sky).
    sh_[0] = glm::vec4(c / 0.282095f, 0.0f);
    // The cube still goes through the prefilter so that a uniform sky checks its normalisation.
    EquirectImage image{1, 1, {constantRadiance}};
    build(ctx, image, options, "constant environment");
}

Environment::Environment(const gpu::Context& ctx, const EquirectImage& image,
                         const EnvironmentOptions& options) {
    validate(options);
    if (image.width == 0 || image.height == 0 ||
        image.texels.size() != size_t(image.width) * image.height)
        throw argumentError("environment image size does not match its texel count");
    sh_ = projectIrradianceSH(image);
    for (glm::vec4& c : sh_) c *= options.intensity;
    build(ctx, image, options, "in-memory environment");
}

void Environment::build(const gpu::Context& ctx, const EquirectImage& image,
                        const EnvironmentOptions& options, const std::string& label) {
    auto start = std::chrono::steady_clock::now();
    const uint32_t size = options.cubeSize;
    const uint32_t levels = std::bit_width(size);  // box chain down to 1x1
    const VkImageUsageFlags usage =
        VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    // Mips stop at 4x4: smaller faces cannot hold even the widest lobe without visible seams.
    specular_ =
        gpu::Image(ctx, {size, size, VK_FORMAT_R16G16B16A16_SFLOAT, levels - 2, 6, true, usage},
                   "render.environment.specular");
    dfg_ = gpu::Image(
        ctx, {options.dfgSize, options.dfgSize, VK_FORMAT_R16G16_SFLOAT, 1, 1, false, usage},
        "render.environment.dfg");
    gpu::Image radiance(ctx, {size, size, VK_FORMAT_R16G16B16A16_SFLOAT, levels, 6, true, usage},
                        "render.environment.radiance");
    sampler_ =
        gpu::createSampler(ctx, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, true);
    ctx.setName(VK_OBJECT_TYPE_SAMPLER, reinterpret_cast<uint64_t>(sampler_.get()),
                "render.environment.sampler");

    gpu::Buffer equirect = uploadEquirect(ctx, image);
    IblPipelines pipelines(ctx);
    const double setupSeconds = secondsSince(start);
    BuildInputs in{equirect,
                   image.width,
                   image.height,
                   options.intensity,
                   radiance,
                   sampler_,
                   options.prefilterSamples};
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        for (const gpu::Image* target : {&specular_, &dfg_, &radiance})
            gpu::transition(cmd, target->get(), target->aspect(), VK_IMAGE_LAYOUT_UNDEFINED,
                            VK_IMAGE_LAYOUT_GENERAL);
        recordDfg(ctx, cmd, pipelines, dfg_);
        recordCubeChain(ctx, cmd, pipelines, in, specular_);
        recordPrefilter(cmd, pipelines, in, specular_);
        toReadOnly(cmd, specular_, 0, VK_REMAINING_MIP_LEVELS);
        toReadOnly(cmd, dfg_, 0, 1);
    });
    log(LogLevel::Debug, label + ": IBL GPU build " + std::to_string(secondsSince(start)) + " s (" +
                             std::to_string(setupSeconds) + " s images, upload and pipelines)");
}

}  // namespace speculum::render
