// Scene upload: one vertex and one index buffer for every primitive, one GPU texture per image
// and colour space, 1x1 defaults, and the flattened draw list.
#include "renderer_impl.hpp"
#include "speculum/render/frustum.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

namespace speculum::render {
namespace {

static_assert(sizeof(Vertex) == 48, "the G-buffer pipelines read the engine's 48-byte Vertex");

uint32_t mipCountFor(uint32_t w, uint32_t h) {
    return uint32_t(std::bit_width(std::max(w, h)));
}

gpu::Image makeTexture(const gpu::Context& ctx, uint32_t w, uint32_t h, const uint8_t* rgba,
                       VkFormat format, const std::string& name) {
    gpu::ImageDesc desc;
    desc.width = w;
    desc.height = h;
    desc.format = format;
    desc.mips = mipCountFor(w, h);
    desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    gpu::Image image(ctx, desc, name);
    auto bytes = std::as_bytes(std::span(rgba, size_t(w) * h * 4));
    gpu::uploadImage(ctx, image, bytes, desc.mips > 1);
    return image;
}

gpu::Image makeSolid(const gpu::Context& ctx, uint8_t r, uint8_t g, uint8_t b, uint8_t a,
                     VkFormat format, const std::string& name) {
    const uint8_t texel[4] = {r, g, b, a};
    return makeTexture(ctx, 1, 1, texel, format, name);
}

struct ImageUse {
    bool srgb = false;    // base colour or emissive
    bool linear = false;  // metallic-roughness or normal
    bool normal = false;
};

bool usable(const Image& image) {
    return image.width > 0 && image.height > 0 &&
           image.rgba8.size() == size_t(image.width) * image.height * 4;
}

// Where each mesh's primitives start in the shared buffers.
struct Range {
    uint32_t firstIndex, indexCount;
    int32_t vertexOffset;
};
using MeshRanges = std::vector<std::vector<Range>>;

// Geometry: primitives packed back to back; draws address them by first index and offset.
MeshRanges uploadGeometry(const gpu::Context& ctx, const Scene& scene, SceneGpu& gpuScene) {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;
    MeshRanges ranges(scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        for (const Primitive& p : scene.meshes[m].primitives) {
            ranges[m].push_back(
                {uint32_t(indices.size()), uint32_t(p.indices.size()), int32_t(vertices.size())});
            vertices.insert(vertices.end(), p.vertices.begin(), p.vertices.end());
            indices.insert(indices.end(), p.indices.begin(), p.indices.end());
        }
    }
    if (!indices.empty()) {
        gpuScene.vertices = gpu::uploadBuffer(ctx, std::as_bytes(std::span(vertices)),
                                              VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "render.vertices");
        gpuScene.indices = gpu::uploadBuffer(ctx, std::as_bytes(std::span(indices)),
                                             VK_BUFFER_USAGE_INDEX_BUFFER_BIT, "render.indices");
    }
    return ranges;
}

// Views of the uploaded images per colour space (null where an image is not used that way),
// and of the 1x1 defaults.
struct ImageViews {
    std::vector<VkImageView> srgb, linear;
    VkImageView white, whiteLinear, flatNormal, black;
};

ImageViews uploadImages(const gpu::Context& ctx, const Scene& scene, SceneGpu& gpuScene) {
    // Which colour spaces each image is sampled in decides its GPU copies.
    std::vector<ImageUse> uses(scene.images.size());
    auto mark = [&](const TextureRef& t, bool srgb, bool normal) {
        if (t.image < 0 || size_t(t.image) >= uses.size()) return;
        (srgb ? uses[t.image].srgb : uses[t.image].linear) = true;
        uses[t.image].normal |= normal;
    };
    for (const Material& m : scene.materials) {
        mark(m.baseColorTexture, true, false);
        mark(m.emissiveTexture, true, false);
        mark(m.metallicRoughnessTexture, false, false);
        mark(m.normalTexture, false, true);
    }

    auto& images = gpuScene.images;
    images.reserve(4 + 2 * scene.images.size());
    images.push_back(
        makeSolid(ctx, 255, 255, 255, 255, VK_FORMAT_R8G8B8A8_SRGB, "render.default.white"));
    images.push_back(makeSolid(ctx, 255, 255, 255, 255, VK_FORMAT_R8G8B8A8_UNORM,
                               "render.default.white_linear"));
    images.push_back(
        makeSolid(ctx, 128, 128, 255, 255, VK_FORMAT_R8G8B8A8_UNORM, "render.default.normal"));
    images.push_back(makeSolid(ctx, 0, 0, 0, 255, VK_FORMAT_R8G8B8A8_SRGB, "render.default.black"));
    ImageViews views{std::vector<VkImageView>(scene.images.size(), VK_NULL_HANDLE),
                     std::vector<VkImageView>(scene.images.size(), VK_NULL_HANDLE),
                     images[0].view(), images[1].view(), images[2].view(), images[3].view()};
    for (size_t i = 0; i < scene.images.size(); ++i) {
        const Image& img = scene.images[i];
        if (!usable(img)) {
            logWarning("render: image '" + img.name + "' has no pixels; using a default");
            continue;
        }
        if (uses[i].srgb) {
            images.push_back(makeTexture(ctx, img.width, img.height, img.rgba8.data(),
                                         VK_FORMAT_R8G8B8A8_SRGB, "render.image." + img.name));
            views.srgb[i] = images.back().view();
        }
        // A placeholder's default pixels mean nothing as a normal map: such images stay flat.
        if (uses[i].linear && !(img.placeholder && uses[i].normal)) {
            images.push_back(makeTexture(ctx, img.width, img.height, img.rgba8.data(),
                                         VK_FORMAT_R8G8B8A8_UNORM,
                                         "render.image." + img.name + ".linear"));
            views.linear[i] = images.back().view();
        }
    }
    return views;
}

VkImageView pick(const TextureRef& t, const std::vector<VkImageView>& views, VkImageView fallback) {
    if (t.image < 0 || size_t(t.image) >= views.size() || !views[t.image]) return fallback;
    return views[t.image];
}

GpuMaterial resolveMaterial(const Scene& scene, const Material& m, const ImageViews& v) {
    GpuMaterial g;
    g.baseColor = m.baseColor;
    g.emissive = m.emissive * m.emissiveStrength;
    g.metallic = m.metallic;
    g.roughness = m.roughness;
    g.normalScale = m.normalTexture.scale;
    g.flags = (m.unlit ? kFlagUnlit : 0u) |
              (reflects(m) ? kFlagReflective : 0u);
    g.doubleSided = m.doubleSided;
    g.baseColorView = pick(m.baseColorTexture, v.srgb, v.white);
    g.metallicRoughnessView = pick(m.metallicRoughnessTexture, v.linear, v.whiteLinear);
    bool placeholderNormal = m.normalTexture.image >= 0 &&
                             size_t(m.normalTexture.image) < scene.images.size() &&
                             scene.images[m.normalTexture.image].placeholder;
    g.normalView = placeholderNormal ? v.flatNormal : pick(m.normalTexture, v.linear, v.flatNormal);
    // glTF: emissive texture multiplies the factor; without one the factor stands alone.
    g.emissiveView = pick(m.emissiveTexture, v.srgb, v.white);
    if (m.emissive == glm::vec3(0.0f)) g.emissiveView = v.black;
    g.untextured = g.baseColorView == v.white && g.metallicRoughnessView == v.whiteLinear &&
                   g.normalView == v.flatNormal &&
                   (g.emissiveView == v.white || g.emissiveView == v.black);
    return g;
}

}  // namespace

SceneGpu uploadScene(const gpu::Context& ctx, const Scene& scene) {
    SceneGpu gpuScene;
    MeshRanges ranges = uploadGeometry(ctx, scene, gpuScene);
    ImageViews views = uploadImages(ctx, scene, gpuScene);
    for (const Material& m : scene.materials) gpuScene.materials.push_back(resolveMaterial(scene, m, views));
    gpuScene.materials.push_back(resolveMaterial(scene, Material{}, views));  // glTF's default material
    if (gpuScene.materials.size() > kMaxIndexedMaterials)
        logWarning("render: the scene has " + std::to_string(scene.materials.size()) +
                   " materials; per-material reflection settings apply to the first " +
                   std::to_string(kMaxIndexedMaterials - 1));
    for (size_t i = 0; i < gpuScene.materials.size(); ++i)
        gpuScene.materials[i].flags |= uint32_t(std::min<size_t>(i, kMaxIndexedMaterials)) << kMaterialIndexShift;
    const uint32_t defaultMaterial = uint32_t(gpuScene.materials.size() - 1);

    for (const Instance& inst : scene.instances) {
        if (inst.mesh < 0 || size_t(inst.mesh) >= scene.meshes.size()) continue;
        const auto& prims = scene.meshes[inst.mesh].primitives;
        bool mirrored = glm::determinant(glm::mat3(inst.world)) < 0.0f;
        for (size_t p = 0; p < prims.size(); ++p) {
            const Range& r = ranges[inst.mesh][p];
            if (r.indexCount == 0) continue;
            int mat = prims[p].material;
            uint32_t material =
                mat >= 0 && size_t(mat) < scene.materials.size() ? uint32_t(mat) : defaultMaterial;
            DrawItem& d = gpuScene.draws.emplace_back(
                DrawItem{r.firstIndex, r.indexCount, r.vertexOffset, material, inst.world, mirrored, inst.node,
                         inst.node >= 0 && scene.nodes[size_t(inst.node)].hiddenPrimary});
            transformBox(inst.world, prims[p].boundsMin, prims[p].boundsMax, d.worldMin, d.worldMax);
        }
    }
    gpuScene.materialSampler =
        gpu::createSampler(ctx, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_REPEAT, true);
    return gpuScene;
}

}  // namespace speculum::render
