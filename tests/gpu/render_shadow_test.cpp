// render.shadow_mask: the sun's visibility per pixel from the depth prepass and the shadow map.
#include "render_test_support.hpp"

#include <gtest/gtest.h>

namespace speculum::render {
namespace {

using test::pixelOf;

class RenderShadow : public test::ValidatedContextTest {};

// A ground plane, a square floating above it and an oblique sun: the mask is 0 in the
// occluder's shadow, 1 on open ground and on the occluder's own sunlit top (no acne there).
TEST_F(RenderShadow, MaskIsZeroUnderAnOccluderAndOneInTheOpen) {
    Scene scene;
    scene.materials.push_back(Material{});
    test::addMesh(scene, test::square({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 10.0f, 0));
    const glm::vec3 occluder{-1.0f, 1.5f, -1.0f};
    const float half = 1.0f;
    test::addMesh(scene, test::square(occluder, {1, 0, 0}, {0, 0, -1}, half, 0));
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.4f, -1.0f, 0.3f));
    sun.intensity = 5.0f;  // well above the sky's ambient
    scene.lights.push_back(sun);
    Renderer renderer(ctx, scene, {.shadowMapSize = 1024});
    CameraState cam = makeCamera({0, 9, 6}, {0, 0, -1}, {0, 1, 0}, 0.9f, 128, 96);
    test::Frame f = test::renderFrame(ctx, renderer, cam);
    ASSERT_TRUE(f.images.count("render.shadow_mask")) << "no shadow mask for a directional light";

    auto mask = [&](glm::vec3 p) {
        glm::ivec2 px = pixelOf(cam, p);
        EXPECT_TRUE(px.x >= 0 && px.y >= 0 && px.x < int(cam.width) && px.y < int(cam.height));
        return f.at("render.shadow_mask", uint32_t(px.x), uint32_t(px.y)).r;
    };
    // The occluder's centre projected along the light onto the ground, and points around it
    // well inside the shadow (which is as large as the occluder).
    glm::vec3 shadowCentre = occluder + sun.direction * (occluder.y / -sun.direction.y);
    for (glm::vec3 d : {glm::vec3(0), glm::vec3(0.5f, 0, 0.5f), glm::vec3(-0.5f, 0, -0.5f)})
        EXPECT_EQ(mask(shadowCentre + d), 0.0f) << "in the shadow, offset " << d.x << "," << d.z;
    for (glm::vec3 p : {glm::vec3(4, 0, 2), glm::vec3(-5, 0, 1), glm::vec3(3, 0, -6),
                        shadowCentre + glm::vec3(0, 0, 3.0f * half)})
        EXPECT_EQ(mask(p), 1.0f) << "in the open at " << p.x << "," << p.z;
    EXPECT_EQ(mask(occluder), 1.0f) << "the occluder's sunlit top shadows itself";

    // Lighting applies the mask: the shadowed ground is darker than the open ground.
    glm::ivec2 dark = pixelOf(cam, shadowCentre), lit = pixelOf(cam, glm::vec3(4, 0, 2));
    EXPECT_LT(f.at("render.linear", dark.x, dark.y).g,
              0.5f * f.at("render.linear", lit.x, lit.y).g);
}

// The shadow map is drawn once and kept (it is fitted to the scene's bounds, not the view): a
// second frame from another camera gets the same mask where both see the ground; hiding the
// occluder (Renderer::setNodeVisible, the game's collected gems) draws it again without the
// shadow, and showing it draws the shadow back. A cache that missed a change would keep the
// shadow of a hidden node.
TEST_F(RenderShadow, TheMapIsKeptAcrossFramesAndRedrawnWhenACasterHides) {
    Scene scene;
    scene.nodes.resize(2);
    scene.materials.push_back(Material{});
    test::addMesh(scene, test::square({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 10.0f, 0));
    const glm::vec3 occluder{-1.0f, 1.5f, -1.0f};
    test::addMesh(scene, test::square(occluder, {1, 0, 0}, {0, 0, -1}, 1.0f, 0));
    scene.instances[0].node = 0;
    scene.instances[1].node = 1;
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.4f, -1.0f, 0.3f));
    sun.intensity = 5.0f;
    scene.lights.push_back(sun);
    Renderer renderer(ctx, scene, {.shadowMapSize = 1024});
    CameraState cam = makeCamera({0, 9, 6}, {0, 0, -1}, {0, 1, 0}, 0.9f, 128, 96);
    const glm::vec3 shadowCentre = occluder + sun.direction * (occluder.y / -sun.direction.y);
    auto maskAt = [&](const test::Frame& f, const CameraState& c, glm::vec3 p) {
        glm::ivec2 px = pixelOf(c, p);
        return f.at("render.shadow_mask", uint32_t(px.x), uint32_t(px.y)).r;
    };
    test::Frame first = test::renderFrame(ctx, renderer, cam);
    ASSERT_EQ(maskAt(first, cam, shadowCentre), 0.0f);
    // Another view, the map as it was: the same shadow, and this camera's own mask is the one a
    // renderer that draws the map for this frame gives, bit for bit.
    CameraState side = makeCamera({6, 7, 4}, {0, 0, -1}, {0, 1, 0}, 0.9f, 128, 96);
    test::Frame kept = test::renderFrame(ctx, renderer, side);
    Renderer fresh(ctx, scene, {.shadowMapSize = 1024});
    test::Frame drawn = test::renderFrame(ctx, fresh, side);
    EXPECT_EQ(kept.images.at("render.shadow_mask"), drawn.images.at("render.shadow_mask"));
    EXPECT_EQ(maskAt(kept, side, shadowCentre), 0.0f);
    renderer.setNodeVisible(1, false);
    EXPECT_EQ(maskAt(test::renderFrame(ctx, renderer, cam), cam, shadowCentre), 1.0f) << "a hidden node's shadow stayed";
    renderer.setNodeVisible(1, true);
    EXPECT_EQ(maskAt(test::renderFrame(ctx, renderer, cam), cam, shadowCentre), 0.0f) << "the shadow did not come back";
}

// No directional light: no shadow passes, and lighting binds a fully lit stand-in.
TEST_F(RenderShadow, NoDirectionalLightMeansNoMask) {
    Scene scene;
    scene.materials.push_back(Material{});
    test::addMesh(scene, test::square({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 10.0f, 0));
    Light lamp;
    lamp.type = LightType::Point;
    lamp.position = {0, 2, 0};
    lamp.intensity = 10.0f;
    scene.lights.push_back(lamp);
    Renderer renderer(ctx, scene, {.shadowMapSize = 256});
    CameraState cam = makeCamera({0, 5, 5}, {0, 0, 0}, {0, 1, 0}, 0.9f, 64, 48);
    test::Frame f = test::renderFrame(ctx, renderer, cam);
    EXPECT_FALSE(f.images.count("render.shadow_mask"));
    glm::vec4 c = f.at("render.linear", 32, 24);
    EXPECT_GT(c.r, 0.0f);
}

}  // namespace
}  // namespace speculum::render
