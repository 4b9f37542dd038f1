// Image-based lighting from an HDR equirectangular environment (EXR through OpenImageIO):
// a cubemap with GGX-prefiltered mips (roughness = mip / (mips - 1)), a DFG lookup table for the
// split-sum approximation, and 9 spherical-harmonic coefficients for diffuse irradiance.
#pragma once

#include "speculum/gpu/resources.hpp"

#include <glm/glm.hpp>

#include <array>
#include <filesystem>

namespace speculum::render {

struct EnvironmentOptions {
    uint32_t cubeSize = 256;        // face size of mip 0
    uint32_t prefilterSamples = 64; // GGX samples per texel for the rough mips
    uint32_t dfgSize = 64;
    float intensity = 1.0f;
};

class Environment {
public:
    // Throws Error(ExitCode::BadInput) naming the file when it cannot be read.
    Environment(const gpu::Context& ctx, const std::filesystem::path& equirectExr,
                const EnvironmentOptions& options = {});
    // A constant-colour environment (tests, scenes without one).
    Environment(const gpu::Context& ctx, glm::vec3 constantRadiance, const EnvironmentOptions& options = {});

    // RGBA16F cube, all mips, SHADER_READ_ONLY_OPTIMAL. Mip m holds the GGX prefilter for
    // roughness m / (mipCount - 1) (mip 0 is the mirror image).
    const gpu::Image& specular() const { return specular_; }
    // RG16F, x = N.V, y = roughness: the split-sum scale and bias (DFG), SHADER_READ_ONLY_OPTIMAL.
    const gpu::Image& dfg() const { return dfg_; }
    // Irradiance SH (L2, 9 coefficients, RGB; already convolved with the cosine lobe and divided
    // by pi so that diffuse = albedo * evalSH(n)).
    const std::array<glm::vec4, 9>& irradianceSH() const { return sh_; }
    VkSampler sampler() const { return sampler_; }  // trilinear, clamp
    uint32_t mipCount() const { return specular_.desc().mips; }

private:
    gpu::Image specular_;
    gpu::Image dfg_;
    gpu::Unique<VkSampler> sampler_;
    std::array<glm::vec4, 9> sh_{};
};

}  // namespace speculum::render
