// Image-based lighting from an HDR equirectangular environment (EXR through OpenImageIO):
// a cubemap with GGX-prefiltered mips (roughness = mip / (mips - 1)), a DFG lookup table for the
// split-sum approximation, and 9 spherical-harmonic coefficients for diffuse irradiance.
#pragma once

#include "speculum/gpu/resources.hpp"
#include "speculum/settings.hpp"

#include <glm/glm.hpp>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace speculum::render {

// The sky convention, shared by the renderer, the reflections module and the Embree reference
// renderer (copy this block where a shader or tool needs it):
//   world space is right-handed, Y up. A unit direction d maps to equirect coordinates
//     u = 0.5 + atan2(d.x, -d.z) / (2 pi)      (u = 0.5 looks down -Z, u = 0.75 looks down +X)
//     v = acos(clamp(d.y, -1, 1)) / pi         (v = 0 is the top row, straight up)
//   texel (i, j) of a W x H image has its centre at u = (i + 0.5) / W, v = (j + 0.5) / H;
//   lookups are bilinear, wrapping in u and clamping in v.
//   Radiance is the file's RGB times EnvironmentOptions::intensity.
glm::vec2 equirectUV(glm::vec3 dir);
glm::vec3 equirectDirection(glm::vec2 uv);  // inverse of equirectUV (unit length)

// An equirectangular RGB radiance map in CPU memory (rows top to bottom).
struct EquirectImage {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<glm::vec3> texels;  // width * height, row-major

    // Bilinear lookup in direction dir with the convention above (dir need not be normalised).
    glm::vec3 sample(glm::vec3 dir) const;
    glm::vec3 texel(int x, int y) const { return texels[size_t(y) * width + size_t(x)]; }
};

// Reads an EXR (any size; RGB, or grey replicated) through OpenImageIO. Non-finite and negative
// values become 0 with a warning. Throws Error(ExitCode::BadInput) naming the file.
EquirectImage loadEquirect(const std::filesystem::path& path);

// Irradiance SH, real L2 basis in the order
//   Y00, Y1-1, Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22
//   = 0.282095, 0.488603 y, 0.488603 z, 0.488603 x, 1.092548 xy, 1.092548 yz,
//     0.315392 (3 z^2 - 1), 1.092548 xz, 0.546274 (x^2 - y^2)
// (n = (x, y, z) in world space, Y up). Coefficients are the radiance projections (solid-angle
// weighted) times A_l / pi with A0 = pi, A1 = 2 pi / 3, A2 = pi / 4, so evalSH(sh, n) is the
// irradiance at normal n divided by pi (diffuse = albedo * evalSH). RGB in xyz, w = 0.
using SH9 = std::array<glm::vec4, 9>;
SH9 projectIrradianceSH(const EquirectImage& image);
glm::vec3 evalSH(const SH9& sh, glm::vec3 n);

// cubeSize and prefilterSamples are render.environment_size and render.environment_samples: their
// defaults are the settings table's (engine/render/render_settings.cpp).
struct EnvironmentOptions {
    static const SettingFields<EnvironmentOptions>& fields();

    uint32_t cubeSize = settingDefault<&EnvironmentOptions::cubeSize>();  // face size of mip 0
    // GGX samples per texel for the rough mips
    uint32_t prefilterSamples = settingDefault<&EnvironmentOptions::prefilterSamples>();
    uint32_t dfgSize = 64;
    float intensity = 1.0f;
};

class Environment {
public:
    // Throws Error(ExitCode::BadInput) naming the file when it cannot be read.
    Environment(const gpu::Context& ctx, const std::filesystem::path& equirectExr,
                const EnvironmentOptions& options = {});
    // A constant-colour environment (tests, scenes without one).
    Environment(const gpu::Context& ctx, glm::vec3 constantRadiance,
                const EnvironmentOptions& options = {});
    // From an image already in memory (synthetic skies in tests).
    Environment(const gpu::Context& ctx, const EquirectImage& image,
                const EnvironmentOptions& options = {});

    // RGBA16F cube, all mips, SHADER_READ_ONLY_OPTIMAL. Mip m holds the GGX prefilter for
    // perceptual roughness m / (mipCount - 1), alpha = roughness^2 (mip 0 is the mirror image):
    // sample with textureLod(cube, R, roughness * (mipCount - 1)). Faces follow the Vulkan cube
    // face selection, so texture(samplerCube, d) is the radiance seen in direction d. The last
    // mip is 4x4 (cubeSize 256 gives 7 mips); cubeSize must be a power of two >= 8. Mip 0 texels
    // are the bilinear sky lookup at their centre direction, or, for skies wider than
    // 4 * cubeSize, the mean of n x n lookups inside the texel (n = ceil(width / (4 cubeSize))).
    const gpu::Image& specular() const { return specular_; }
    // RG16F, x = N.V, y = perceptual roughness (texel centres: texel i holds (i + 0.5) / size, so
    // sample with texture(dfg, vec2(NdotV, roughness)) and a linear clamp sampler): the split-sum
    // scale and bias of F0 for GGX (alpha = roughness^2), height-correlated Smith visibility and
    // Schlick Fresnel, so specular = prefiltered * (F0 * dfg.x + dfg.y). SHADER_READ_ONLY_OPTIMAL.
    const gpu::Image& dfg() const { return dfg_; }
    // Irradiance SH (L2, 9 coefficients, RGB; already convolved with the cosine lobe and divided
    // by pi so that diffuse = albedo * evalSH(n)).
    const SH9& irradianceSH() const { return sh_; }
    VkSampler sampler() const { return sampler_; }  // trilinear, clamp
    uint32_t mipCount() const { return specular_.desc().mips; }

private:
    gpu::Image specular_;
    gpu::Image dfg_;
    gpu::Unique<VkSampler> sampler_;
    SH9 sh_{};

    void build(const gpu::Context& ctx, const EquirectImage& image,
               const EnvironmentOptions& options, const std::string& label);
};

}  // namespace speculum::render
