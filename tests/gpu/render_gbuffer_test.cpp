// The renderer's G-buffer and tonemap against CPU evaluations of the same conventions: an unlit
// quad's base colour through the ACES fit and sRGB, and back-face culling.
#include "render_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace speculum::render {
namespace {

using test::Frame;
using test::pixelOf;

float srgbEncode(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
float aces(float x) {
    return std::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

using test::RenderPasses;

TEST_F(RenderPasses, UnlitQuadWritesItsBaseColourExactly) {
    Scene scene;
    Material m;
    m.unlit = true;
    m.baseColor = {0.2f, 0.45f, 0.8f, 1.0f};
    m.emissive = {5.0f, 5.0f, 5.0f};  // ignored by unlit
    scene.materials.push_back(m);
    test::addMesh(scene, test::square({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10.0f, 0));
    Renderer renderer(ctx, scene, {.shadowMapSize = 256});
    CameraState cam = makeCamera({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 0.8f, 64, 48);
    Frame f = test::renderFrame(ctx, renderer, cam);
    for (uint32_t y = 0; y < f.height; ++y) {
        for (uint32_t x = 0; x < f.width; ++x) {
            glm::vec4 c = f.at("render.linear", x, y);
            for (int i = 0; i < 3; ++i)
                ASSERT_NEAR(c[i], m.baseColor[i], 5e-4f * m.baseColor[i]) << x << "," << y;
        }
    }
    glm::vec4 color = f.at("render.color", 10, 10);
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(color[i], srgbEncode(aces(m.baseColor[i])), 1.0f / 255.0f);
}

TEST_F(RenderPasses, BackFacesAreCulledUnlessDoubleSided) {
    Scene scene;
    auto unlit = [](glm::vec3 c, bool doubleSided) {
        Material m;
        m.unlit = true;
        m.baseColor = glm::vec4(c, 1.0f);
        m.doubleSided = doubleSided;
        return m;
    };
    scene.materials = {unlit({1, 0, 0}, false), unlit({0, 1, 0}, false), unlit({0, 0, 1}, true)};
    test::addMesh(scene,
                  test::square({-1.0f, 0.5f, 0}, {1, 0, 0}, {0, 1, 0}, 0.4f, 0));  // faces camera
    test::addMesh(scene,
                  test::square({1.0f, 0.5f, 0}, {0, 1, 0}, {1, 0, 0}, 0.4f, 1));  // faces away
    test::addMesh(scene,
                  test::square({0.0f, -0.6f, 0}, {0, 1, 0}, {1, 0, 0}, 0.4f, 2));  // away, 2-sided
    Renderer renderer(ctx, scene, {.shadowMapSize = 256});
    CameraState cam = makeCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.8f, 64, 64);
    Frame f = test::renderFrame(ctx, renderer, cam);

    auto at = [&](glm::vec3 p) {
        glm::ivec2 px = pixelOf(cam, p);
        return f.at("render.linear", px.x, px.y);
    };
    EXPECT_NEAR(at({-1.0f, 0.5f, 0}).r, 1.0f, 1e-3f);
    glm::vec4 culled = at({1.0f, 0.5f, 0});
    EXPECT_NEAR(culled.g, 0.6f, 1e-2f)
        << "a single-sided back face was drawn";  // the grey-blue sky
    EXPECT_NEAR(at({0.0f, -0.6f, 0}).b, 1.0f, 1e-3f);
    glm::ivec2 px = pixelOf(cam, {0.0f, -0.6f, 0});
    glm::vec4 normal = f.at("render.normal", px.x, px.y);
    EXPECT_NEAR(normal.z, 1.0f, 1e-3f)
        << "a double-sided back face keeps its normal facing the viewer";
    glm::vec4 emissive = f.at("render.emissive", px.x, px.y);
    // The flag bits; the material's index sits above them (kMaterialIndexShift).
    EXPECT_EQ(uint32_t(emissive.a) & ((1u << kMaterialIndexShift) - 1u), kFlagUnlit);
}

}  // namespace
}  // namespace speculum::render
