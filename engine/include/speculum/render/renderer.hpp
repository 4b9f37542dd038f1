// The deferred renderer: depth prepass, shadow map and screen-space shadow mask for one
// directional light, G-buffer, GGX + Lambert lighting with image-based ambient, tonemapping.
// It adds its passes to a frame graph and returns typed handles, like every module.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/render/environment.hpp"
#include "speculum/scene.hpp"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace speculum::render {

// G-buffer and output formats; fixed so that modules and tests can rely on them.
inline constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;              // reversed-Z, 1 = near
inline constexpr VkFormat kAlbedoFormat = VK_FORMAT_R8G8B8A8_UNORM;         // rgb albedo, a metallic
inline constexpr VkFormat kNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;    // xyz world normal, w roughness
inline constexpr VkFormat kEmissiveFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // rgb emissive, a material flags
inline constexpr VkFormat kMotionFormat = VK_FORMAT_R16G16_SFLOAT;          // uv(now) - uv(previous frame)
inline constexpr VkFormat kLinearFormat = VK_FORMAT_R16G16B16A16_SFLOAT;    // HDR linear colour
inline constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;          // tonemapped, sRGB-encoded

// Material flag bits stored in emissive.a, with the material's index above them
// (emissive.a = flags | index << kMaterialIndexShift): modules look per-material settings up by
// that index. A 16-bit float holds integers up to 2048 exactly, so up to 511 materials.
inline constexpr uint32_t kFlagUnlit = 1;
inline constexpr uint32_t kFlagReflective = 2;  // reflects (scene.hpp reflects(): lit, mode != off)
inline constexpr uint32_t kMaterialIndexShift = 2;
inline constexpr uint32_t kMaxIndexedMaterials = 511;

// Everything a pass needs to know about the view. Projection is reversed-Z with an infinite far
// plane; pixel (x, y) has its centre at ((x + 0.5) / w, (y + 0.5) / h) in UV, y down.
struct CameraState {
    glm::mat4 view{1.0f};
    glm::mat4 proj{1.0f};
    glm::mat4 viewProj{1.0f};
    glm::mat4 invViewProj{1.0f};
    glm::vec3 position{0.0f};
    float yfov = 1.0f;
    float znear = 0.05f;
    uint32_t width = 1;
    uint32_t height = 1;
};
CameraState makeCamera(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float yfovRadians, uint32_t width,
                       uint32_t height, float znear = 0.05f);
CameraState makeCamera(const Camera& camera, uint32_t width, uint32_t height);
// Frames the scene's bounds from a fixed diagonal direction.
CameraState frameBounds(const Scene& scene, uint32_t width, uint32_t height);
// World-space ray through the centre of pixel (x, y): the same convention as the rasterizer.
void primaryRay(const CameraState& camera, float px, float py, glm::vec3& origin, glm::vec3& direction);

// The render.* settings (app::engineSettingsTable()), whose rows bind these fields and
// environment's: fromSettings<RendererOptions>() fills them, and the defaults are the table's.
struct RendererOptions {
    static const SettingFields<RendererOptions>& fields();

    uint32_t shadowMapSize = settingDefault<&RendererOptions::shadowMapSize>();
    float exposure = settingDefault<&RendererOptions::exposure>();  // multiplies the scene's extras.exposure
    EnvironmentOptions environment;
};

// Per lighting pass: what the modules that follow it do this frame.
struct LightingOptions {
    // A module composites the specular ambient of reflective pixels (kFlagReflective) itself, so
    // render.lighting leaves it out there.
    bool moduleSpecular = false;
};

struct FrameInputs {
    CameraState camera;
    CameraState previousCamera;  // same as camera on the first frame
    // The player's view: nodes with Node::hiddenPrimary are left out of its depth prepass and
    // G-buffer (they still cast shadows and appear in probe and CMO captures, which leave this
    // false).
    bool primaryView = false;
    // The camera is reflected in a plane (a planar probe's view, modules/probes): its
    // view matrix has a negative determinant, so every draw's front face flips.
    bool mirrored = false;
    // False for a local probe's capture (modules/probes): render.lighting leaves the direct
    // lights' specular out. A highlight belongs to the camera that sees it, and a probe's cube is
    // read from everywhere but its capture point: a lamp's highlight on a glossy floor, baked
    // where the capture point sees it, lit the closed room's rough walls in blotches and the
    // gallery's chrome objects where their rays met the floor elsewhere
    // (modules/probes/MEASUREMENTS.md).
    bool directSpecular = true;
};

// The handles the renderer's passes produce. `lit` is the lit HDR image before reflections are
// composited; modules add to it and hand the result to tonemap().
struct GBuffer {
    TextureHandle depth;
    TextureHandle albedo;
    TextureHandle normal;
    TextureHandle emissive;
    TextureHandle motion;
    // render.shadow_mask: R8 visibility of the shadowed directional light per pixel (1 lit);
    // invalid when the scene has no directional light.
    TextureHandle shadowMask;
};

// A pass's read of the four surface attachments (depth, albedo, normal, emissive) as sampled
// textures: what shading a G-buffer pixel needs (render.lighting, probes.capture_bounce, probes.cmo_store). The
// motion and the shadow mask are left to the passes that use them.
inline GBuffer readSurfaceAttachments(PassBuilder& b, const GBuffer& g) {
    GBuffer r;
    r.depth = b.read(g.depth, TextureUsage::Sampled);
    r.albedo = b.read(g.albedo, TextureUsage::Sampled);
    r.normal = b.read(g.normal, TextureUsage::Sampled);
    r.emissive = b.read(g.emissive, TextureUsage::Sampled);
    return r;
}

class Renderer {
public:
    // Uploads meshes, textures and the environment named by the scene's extras (or a grey sky).
    Renderer(const gpu::Context& ctx, const Scene& scene, const RendererOptions& options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // render.depth_prepass, render.shadow, render.shadow_mask, render.gbuffer. The G-buffer
    // tests against the prepass's depth without writing it; `depth` is that final depth.
    GBuffer addGBufferPasses(FrameGraph& graph, const FrameInputs& frame);
    // render.lighting: punctual lights (GGX + Lambert), shadows, IBL ambient, sky, emissive.
    TextureHandle addLightingPass(FrameGraph& graph, const FrameInputs& frame, const GBuffer& gbuffer,
                                  const LightingOptions& lighting = {});
    // render.tonemap: exposure, ACES fit, sRGB encode into an RGBA8 image.
    TextureHandle addTonemapPass(FrameGraph& graph, TextureHandle linear);

    // Re-reads the scene's material factors (base colour, metallic, roughness, whether it
    // reflects) for the frames recorded from now on: the editor's sliders move them live.
    // Textures, emissive and alpha stay as uploaded.
    void updateMaterialFactors();
    // Leaves a node's meshes out of every pass from the next recorded frame on (or puts them
    // back): the game's collected items. Probes keep what they captured until they bake again.
    void setNodeVisible(int node, bool visible);

    const Environment& environment() const;
    // The scene's lights and irradiance SH as specialization constants (ids 0-287), for passes
    // that include shaders/engine/scene_lights.glsl and shade surfaces again.
    const std::vector<uint32_t>& lightingConstants() const;
    const Scene& scene() const;
    RendererOptions& options();

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace speculum::render
