// Internal to speculum-reference: the sky (radiance, irradiance SH, split-sum tables), the Embree
// scene and the engine's shading model in C++.
#pragma once

#include "reference.hpp"

#include <embree3/rtcore.h>

#include <array>
#include <mutex>
#include <cstdint>
#include <vector>

namespace speculum::reference {

constexpr float kPi = 3.14159265358979323846f;

// ---- sampling ------------------------------------------------------------------------------

// PCG32 (O'Neill): small, fast and good enough for Monte Carlo; one stream per pixel keeps the
// image independent of the thread count.
class Rng {
public:
    Rng(uint64_t seed, uint64_t stream);
    uint32_t next();
    float uniform();  // [0, 1)

private:
    uint64_t state_ = 0, inc_ = 1;
};

glm::vec2 hammersley(uint32_t i, uint32_t n);
// Orthonormal basis with n as the third column (Frisvad, as shaders/engine/ibl_common.glsl).
glm::mat3 tangentFrame(glm::vec3 n);
// GGX half vector in tangent space with pdf D(h) * NdotH (ibl_common.glsl).
glm::vec3 importanceSampleGGX(glm::vec2 xi, float alpha);
// Heitz 2018: a GGX visible normal for the tangent-space view direction v (v.z > 0).
glm::vec3 sampleVisibleNormal(glm::vec3 v, float alpha, glm::vec2 xi);

// ---- the engine's BRDF (shaders/common/brdf.glsl) -------------------------------------------

constexpr float kMinRoughness = 0.045f;
float D_GGX(float NoH, float alpha);
float V_SmithGGXCorrelated(float NoV, float NoL, float alpha);
float smithG1(float NoV, float alpha);
glm::vec3 F_Schlick(glm::vec3 f0, float VoH);
glm::vec3 evalBRDFCos(glm::vec3 n, glm::vec3 v, glm::vec3 l, glm::vec3 baseColor, float metallic,
                      float perceptualRoughness);
inline glm::vec3 specularF0(glm::vec3 base, float metallic) {
    return glm::mix(glm::vec3(0.04f), base, metallic);
}
inline glm::vec3 diffuseColor(glm::vec3 base, float metallic) { return base * (1.0f - metallic); }

// ---- the sky ------------------------------------------------------------------------------

// The environment the engine's renderer would build for this scene (engine/render/renderer.cpp:
// extras.environment, else a constant grey-blue), in CPU form.
class Sky {
public:
    Sky(const Scene& scene, unsigned threads);
    glm::vec3 radiance(glm::vec3 dir) const;  // bilinear equirect lookup (environment.hpp)
    glm::vec3 irradianceOverPi(glm::vec3 n) const;  // evalSH
    // The split-sum prefilter (N = V = R) for perceptual roughness r, interpolated between
    // levels 1/16 apart (the engine's cube has mips 1/6 apart).
    glm::vec3 prefiltered(glm::vec3 dir, float roughness) const;
    // The DFG table (scale, bias), built as shaders/engine/ibl_dfg.comp builds it.
    glm::vec2 dfg(float NoV, float roughness) const;
    // Builds the prefiltered levels now rather than inside the first frame (whose time is reported).
    void prepare() const;
    float sceneExposure() const { return exposure_; }

private:
    render::EquirectImage image_;
    std::vector<render::EquirectImage> mips_;    // box pyramid of image_ (filtered sampling)
    // levels_[k]: roughness (k + 1) / kLevels. Built on first use: a scene whose every surface
    // is reflective (most tests) never needs them.
    mutable std::vector<render::EquirectImage> levels_;
    mutable std::once_flag levelsBuilt_;
    unsigned threads_ = 1;
    render::SH9 sh_{};
    std::vector<glm::vec2> dfg_;
    float exposure_ = 1.0f;

    glm::vec3 sampleLod(glm::vec3 dir, float lod) const;
    void buildLevels() const;
};

// ---- Embree --------------------------------------------------------------------------------

// One primitive of one instance, in world space, wound so that cross(b - a, c - a) points out of
// glTF's front face even under mirroring transforms.
struct Geometry {
    int material = -1;  // index into Scene::materials; -1: the glTF default
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec4> tangents;
    std::vector<glm::vec2> uvs;
    std::vector<uint32_t> indices;
};

struct Hit {
    bool valid = false;
    float t = 0.0f;
    uint32_t geometry = 0, primitive = 0;
    float u = 0.0f, v = 0.0f;
};

class Tracer {
public:
    Tracer(const Scene& scene, const std::vector<bool>& doubleSided);
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    // Closest hit that a rasterizer would show: back faces of single-sided materials are skipped
    // (the engine culls them).
    Hit intersect(glm::vec3 origin, glm::vec3 dir, uint64_t& rays) const;
    // Shadow rays see both faces: the engine's shadow map is drawn without culling.
    bool occluded(glm::vec3 origin, glm::vec3 dir, uint64_t& rays) const;
    const Geometry& geometry(uint32_t id) const { return geometries_[id]; }

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<Geometry> geometries_;
    std::vector<bool> doubleSided_;  // per material (+ the default last)
};

// Offset that keeps secondary rays off the surface they start on.
glm::vec3 offsetOrigin(glm::vec3 p, glm::vec3 geometricNormal, glm::vec3 dir);

}  // namespace speculum::reference
