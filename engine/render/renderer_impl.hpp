// Internal to speculum_render: the state Renderer's passes share.
#pragma once

#include "speculum/render/renderer.hpp"

#include <memory>
#include <vector>

namespace speculum::render {

// One indexed draw of a primitive under an instance transform.
struct DrawItem {
    uint32_t firstIndex = 0;
    uint32_t indexCount = 0;
    int32_t vertexOffset = 0;
    uint32_t material = 0;  // index into SceneGpu::materials (the default material is last)
    glm::mat4 model{1.0f};
    bool mirrored = false;  // negative determinant: winding and facing are inverted
    int node = -1;
    bool hiddenPrimary = false;  // Node::hiddenPrimary: not drawn into FrameInputs::primaryView
    bool hidden = false;         // Renderer::setNodeVisible(false): not drawn at all
    glm::vec3 worldMin{0.0f}, worldMax{0.0f};  // the primitive's bounds under `model` (frustum.hpp)
    bool drawnIn(bool primaryView) const { return !hidden && !(primaryView && hiddenPrimary); }
};

// A material resolved for drawing: factors and the views its four textures use.
struct GpuMaterial {
    glm::vec4 baseColor{1.0f};
    glm::vec3 emissive{0.0f};  // already times emissiveStrength
    float metallic = 1.0f;
    float roughness = 1.0f;
    float normalScale = 1.0f;
    uint32_t flags = 0;  // kFlagUnlit | kFlagReflective
    bool doubleSided = false;
    bool untextured = false;  // all four views are 1x1 defaults: the G-buffer samples none
    VkImageView baseColorView = VK_NULL_HANDLE;
    VkImageView metallicRoughnessView = VK_NULL_HANDLE;
    VkImageView normalView = VK_NULL_HANDLE;
    VkImageView emissiveView = VK_NULL_HANDLE;
};

// The scene's geometry and textures on the GPU (scene_gpu.cpp).
struct SceneGpu {
    gpu::Buffer vertices;
    gpu::Buffer indices;
    std::vector<DrawItem> draws;
    std::vector<GpuMaterial> materials;
    std::vector<gpu::Image> images;          // scene images (sRGB and/or UNORM) and the defaults
    gpu::Unique<VkSampler> materialSampler;  // trilinear, repeat
};
SceneGpu uploadScene(const gpu::Context& ctx, const Scene& scene);

// Orthographic reversed-Z projection for the shadow map (camera.cpp).
glm::mat4 orthographicShadowProjection(float halfExtent, float znear, float zfar);

// World to shadow-map clip space for the first directional light, fitted to the scene bounds.
struct ShadowSetup {
    bool enabled = false;
    glm::mat4 viewProj{1.0f};
    glm::vec3 toLight{0.0f, 1.0f, 0.0f};  // unit
    float worldTexel = 0.0f;              // world size of one shadow texel
    float depthTexel = 0.0f;              // worldTexel in shadow depth units
};

// Binds the scene's vertex and index buffers (gbuffer.cpp).
void bindSceneGeometry(VkCommandBuffer cmd, const SceneGpu& scene);
// A fullscreen-triangle pipeline (fullscreen.vert, no vertex input, no depth, no culling)
// writing one colour target; callers add push constants and constants (bindings: the shader).
gpu::GraphicsPipelineDesc fullscreenPipelineDesc(const std::string& fragmentShader, VkFormat color,
                                                 const std::string& name);
// Begins rendering into one colour attachment that a fullscreen triangle (fullscreen.vert)
// covers entirely (load DONT_CARE), with the viewport and scissor set to extent.
void beginFullscreenRendering(VkCommandBuffer cmd, VkExtent2D extent, VkImageView color);
ShadowSetup fitShadow(const Scene& scene, uint32_t mapSize);

struct Renderer::Impl {
    const gpu::Context& ctx;
    const Scene& scene;
    RendererOptions options;
    std::unique_ptr<Environment> environment;
    SceneGpu gpuScene;
    ShadowSetup shadow;

    gpu::Buffer frameConstants;  // viewProj, prevViewProj: updated in the depth prepass
    gpu::Buffer sceneShadow;     // the shadow mask's static uniforms (lighting.cpp)
    gpu::Unique<VkSampler> nearestSampler;
    gpu::Unique<VkSampler> shadowCompareSampler;  // textureGather with depth compare
    gpu::Image dummyShadowMask;  // bound when there is no directional light
    // The shadow map lives across frames: it is fitted to the scene's bounds, not to the view,
    // so it changes only when what casts changes (setNodeVisible) or its size does. Rendered
    // again every frame it cost 10-15 ms of a frame on lavapipe, and as much again in every
    // planar probe's view (MEASUREMENTS issue 23). shadowDrawn is the shadowCasters revision it
    // holds (0: none yet).
    gpu::Image shadowMap;
    uint64_t shadowCasters = 1;
    uint64_t shadowDrawn = 0;

    gpu::Pipeline shadowPipeline;
    gpu::Pipeline shadowMaskPipeline;
    // Indexed by CullKind (gbuffer.cpp): the prepass must cull exactly as the G-buffer does.
    gpu::Pipeline prepassPipelines[3];
    gpu::Pipeline gbufferPipelines[2][3];  // [GpuMaterial::untextured][CullKind]
    gpu::Pipeline lightingPipeline;
    std::vector<uint32_t> lightingSpecialization;  // lighting.frag's constants (scene_lights.glsl)
    gpu::Pipeline tonemapPipeline;

    Impl(const gpu::Context& c, const Scene& s, const RendererOptions& o);
    void createGBufferPipelines();
    void createShadowResources();
    void createLightingResources();
    void createTonemapPipeline();
    TextureHandle addDepthPrepass(FrameGraph& graph, const FrameInputs& frame);
    TextureHandle addShadowPasses(FrameGraph& graph, const FrameInputs& frame, TextureHandle depth);
    void recordDepthPrepass(VkCommandBuffer cmd, const FrameInputs& frame, VkExtent2D extent,
                            VkImageView depth) const;
    void recordShadow(VkCommandBuffer cmd, VkImageView map, uint32_t size) const;
    void recordShadowMask(PassContext& pass, const FrameInputs& frame, TextureHandle depth,
                          TextureHandle map, TextureHandle out) const;
    void recordGBuffer(VkCommandBuffer cmd, const FrameInputs& frame, VkExtent2D extent,
                       const std::vector<VkImageView>& colors, VkImageView depth) const;
    void recordLighting(PassContext& pass, const FrameInputs& frame, const GBuffer& g,
                        TextureHandle out, const LightingOptions& lighting) const;
    void recordTonemap(PassContext& pass, TextureHandle linear, TextureHandle out) const;
};

}  // namespace speculum::render
