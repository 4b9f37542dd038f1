// speculum-reference: the Embree ground-truth renderer (docs/design.md section 7, ground truth). It shades every
// hit point with the engine's model (shaders/engine/lighting.frag, shaders/common/brdf.glsl)
// and replaces the split-sum specular ambient of reflective materials by traced reflections:
// exact mirror recursion, GGX visible-normal sampling for glossy lobes. README.md in this folder
// gives the estimator and the conventions.
#pragma once

#include "speculum/render/environment.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace speculum::reference {

// The estimator's version: bump it with any change that moves a reference image (sampling,
// shading, the scene loader's output). The converged references in assets/references are keyed
// by it (tests/reference/store.py reads this line), so a bump marks every one of them stale and
// the reference.store_fresh test fails until they are rendered again.
constexpr int kEstimatorVersion = 2;

// The edge between the mirror band and the rough band of the scores (issue 24): reflection
// roughness below it is a mirror or a narrow glossy lobe.
constexpr float kRoughBand = 0.3f;

struct Options {
    uint32_t spp = 64;     // reflection-lobe samples per pixel (mirrors need 1)
    uint32_t bounces = 2;  // reflective surfaces traced this deep; deeper ones use the split sum
    uint64_t seed = 1;
    uint32_t threads = 0;  // 0: every hardware thread
    float exposure = 1.0f;  // render.exposure; multiplies the scene's extras.exposure
    // Adaptive sampling (README.md, "converged references"): a reflective pixel takes batches of
    // `spp` stratified samples, each an independent estimate, until the standard error of their
    // mean, in display units (times the exposure, clamped to [0, 1]), is at most `targetError`
    // after at least `minBatches`, or it has `maxSpp` samples. targetError 0: one batch.
    float targetError = 0.0f;
    uint32_t minBatches = 4;
    uint32_t maxSpp = 0;  // 0: spp (no adaptivity)
    // The cap for pixels of the rough band (reflection roughness >= kRoughBand): their wide lobes
    // converge slowest and the accuracy targets score the mirror band. 0: maxSpp.
    uint32_t roughMaxSpp = 0;
    // Called with (rows done, rows) from the render threads' coordinator; may be empty.
    std::function<void(uint32_t, uint32_t)> progress;
};

// One rendered view; images are row-major, top row first, like the engine's AOVs.
struct Frame {
    uint32_t width = 0, height = 0;
    std::vector<glm::vec3> linear;      // HDR colour before tonemapping
    std::vector<glm::vec3> reflection;  // pre-Fresnel reflection radiance; 0 off reflective pixels
    std::vector<float> depth;           // reversed-Z depth-buffer value (1 near plane, 0 sky)
    std::vector<glm::vec3> normal;      // world shading normal; 0 for sky
    std::vector<float> reflective;      // 1 where the visible surface is reflective
    std::vector<float> roughness;       // the reflection's roughness on reflective pixels, else 0 (score bands)
    std::vector<float> samples;         // lobe samples the reflection took (adaptive sampling); 0 elsewhere
    // The standard error of the reflection in display units (the largest channel's, from the
    // spread of its batches); -1 where it took one batch (unknown), 0 off reflective pixels.
    std::vector<float> stderror;
    double seconds = 0.0;
    uint64_t rays = 0;  // every Embree query: primary, reflection and shadow rays
};

class Renderer {
public:
    // Builds the Embree scene, loads the sky named by the scene's extras (or the engine's grey
    // default) and precomputes the split-sum tables. Throws speculum::Error like the engine.
    Renderer(const Scene& scene, const Options& options);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    Frame render(const render::CameraState& camera) const;
    // render.exposure times the scene's extras.exposure: what the engine's tonemap multiplies by.
    float exposure() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// The engine's tonemap (shaders/engine/tonemap.frag) with the exact sRGB curve: display values
// in [0, 1].
glm::vec3 tonemap(glm::vec3 linear, float exposure);

}  // namespace speculum::reference
