// The renderer's lighting pass against CPU evaluations of the same BRDF (brdf.glsl in C++), the
// sun, image-based light through the DFG table, and the scene's exposure.
#include "render_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace speculum::render {
namespace {

using test::Frame;
using test::pixelOf;

constexpr float kPi = std::numbers::pi_v<float>;

// Bilinear lookup with clamp-to-edge and texel centres at (i + 0.5) / size, like the sampler.
glm::vec2 sampleBilinear(const std::vector<float>& rgba, uint32_t w, uint32_t h, glm::vec2 uv) {
    glm::vec2 p = uv * glm::vec2(w, h) - 0.5f;
    glm::ivec2 i0 = glm::ivec2(glm::floor(p));
    glm::vec2 f = p - glm::vec2(i0);
    auto at = [&](int x, int y) {
        x = std::clamp(x, 0, int(w) - 1);
        y = std::clamp(y, 0, int(h) - 1);
        return glm::vec2(rgba[(size_t(y) * w + x) * 4], rgba[(size_t(y) * w + x) * 4 + 1]);
    };
    return glm::mix(glm::mix(at(i0.x, i0.y), at(i0.x + 1, i0.y), f.x),
                    glm::mix(at(i0.x, i0.y + 1), at(i0.x + 1, i0.y + 1), f.x), f.y);
}

// brdf.glsl's evalBRDFCos in C++.
glm::vec3 brdfCos(glm::vec3 n, glm::vec3 v, glm::vec3 l, glm::vec3 base, float metallic,
                  float rough) {
    float NoL = glm::dot(n, l);
    if (NoL <= 0.0f) return glm::vec3(0.0f);
    glm::vec3 h = glm::normalize(v + l);
    float NoV = std::max(glm::dot(n, v), 1e-4f);
    float NoH = std::clamp(glm::dot(n, h), 0.0f, 1.0f);
    float VoH = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
    float r = std::clamp(rough, 0.045f, 1.0f);
    float a = r * r, a2 = a * a;
    float d = (NoH * a2 - NoH) * NoH + 1.0f;
    float D = a2 / (kPi * d * d);
    float V = 0.5f / (NoL * std::sqrt(NoV * NoV * (1 - a2) + a2) +
                      NoV * std::sqrt(NoL * NoL * (1 - a2) + a2));
    glm::vec3 f0 = glm::mix(glm::vec3(0.04f), base, metallic);
    glm::vec3 F = f0 + (1.0f - f0) * std::pow(1.0f - VoH, 5.0f);
    return (base * (1.0f - metallic) / kPi + D * V * F) * NoL;
}

using test::RenderPasses;

TEST_F(RenderPasses, LambertPlaneUnderADirectionalLightMatchesTheCpu) {
    Scene scene;
    Material plane;
    plane.baseColor = {0.8f, 0.6f, 0.4f, 1.0f};
    plane.metallic = 0.0f;
    plane.roughness = 1.0f;
    scene.materials.push_back(plane);
    test::addMesh(scene, test::square({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 10.0f, 0));
    // An occluder floating above the plane: single-sided, facing up, still casts.
    const glm::vec3 occluder{-3.0f, 1.0f, -3.0f};
    test::addMesh(scene, test::square(occluder, {1, 0, 0}, {0, 0, -1}, 0.6f, 0));
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
    sun.color = {1.0f, 0.9f, 0.8f};
    sun.intensity = 2.0f;
    scene.lights.push_back(sun);
    // The scene names no environment: the renderer's constant grey-blue sky lights it.
    const glm::vec3 sky{0.5f, 0.6f, 0.8f};
    Renderer renderer(ctx, scene, {.shadowMapSize = 1024});

    CameraState cam = makeCamera({0, 3, 4}, {0, 0, -1}, {0, 1, 0}, 0.9f, 96, 64);
    Frame f = test::renderFrame(ctx, renderer, cam);

    const gpu::Image& dfgImage = renderer.environment().dfg();
    std::vector<float> dfg = gpu::readImageRGBA(ctx, dfgImage.get(), dfgImage.desc(),
                                                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    glm::vec3 base = glm::vec3(plane.baseColor);
    glm::vec3 n{0, 1, 0};
    auto expected = [&](glm::vec3 v, bool lit) {
        glm::vec3 c =
            lit ? brdfCos(n, v, -sun.direction, base, 0.0f, 1.0f) * sun.color * sun.intensity
                : glm::vec3(0.0f);
        c += base * evalSH(renderer.environment().irradianceSH(), n);
        glm::vec2 ab = sampleBilinear(dfg, dfgImage.desc().width, dfgImage.desc().height,
                                      {std::clamp(glm::dot(n, v), 0.0f, 1.0f), 1.0f});
        c += sky * (0.04f * ab.x + ab.y);
        return c;
    };
    int checked = 0;
    for (uint32_t y = 36; y < 64; y += 9) {
        for (uint32_t x = 50; x < 96; x += 15) {
            glm::vec3 origin, dir;
            primaryRay(cam, float(x), float(y), origin, dir);
            ASSERT_LT(dir.y, 0.0f);
            glm::vec3 p = origin + dir * (-origin.y / dir.y);
            glm::vec3 want = expected(-dir, true);
            glm::vec4 got = f.at("render.linear", x, y);
            for (int i = 0; i < 3; ++i)
                EXPECT_NEAR(got[i], want[i], 1e-2f)
                    << "pixel " << x << "," << y << " channel " << i;
            ++checked;
        }
    }
    EXPECT_GE(checked, 9);

    // Straight under the occluder along the light: only ambient arrives.
    glm::vec3 shadowed = occluder + sun.direction * (occluder.y / -sun.direction.y);
    glm::ivec2 px = pixelOf(cam, shadowed);
    glm::vec3 origin, dir;
    primaryRay(cam, float(px.x), float(px.y), origin, dir);
    glm::vec3 want = expected(-dir, false);
    glm::vec4 got = f.at("render.linear", px.x, px.y);
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(got[i], want[i], 1e-2f) << "shadowed pixel channel " << i;
    // The sky: the environment's radiance.
    glm::vec4 top = f.at("render.linear", 48, 0);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(top[i], sky[i], 2e-3f);
}

// The scene's extras.exposure sets the exposure and RendererOptions::exposure (the
// render.exposure setting) scales it, so that a user's adjustment is relative to the scene.
TEST_F(RenderPasses, SceneExposureMultipliesTheExposureOption) {
    Scene scene;
    nlohmann::json gltfScene = {{"nodes", nlohmann::json::array()},
                                {"extras", {{"exposure", 4.0}}}};
    scene.document = {{"scenes", {gltfScene}}};
    Renderer renderer(ctx, scene, {.shadowMapSize = 256, .exposure = 0.5f});
    EXPECT_FLOAT_EQ(renderer.options().exposure, 2.0f);
    scene.document["scenes"][0]["extras"].erase("exposure");
    Renderer plain(ctx, scene, {.shadowMapSize = 256, .exposure = 0.5f});
    EXPECT_FLOAT_EQ(plain.options().exposure, 0.5f);
}

}  // namespace
}  // namespace speculum::render
