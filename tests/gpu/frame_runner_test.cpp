// The frame runner's AOVs against CPU geometry: depth where a primary ray meets a plane, and
// motion vectors from reprojecting that point with the previous frame's camera.
#include "render_test_support.hpp"

#include "speculum/app/frame_runner.hpp"
#include "speculum/core.hpp"

#include <gtest/gtest.h>

using namespace speculum;

namespace {

Scene floorScene() {
    Scene scene;
    Material grey;
    grey.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    grey.metallic = 0.0f;
    grey.roughness = 0.8f;
    scene.materials.push_back(grey);
    // A 20 m floor at y = 0 facing +Y.
    render::test::addMesh(scene, render::test::square({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 10.0f, 0));
    return scene;
}

// Where the primary ray through pixel (x, y) meets the plane y = 0.
glm::vec3 floorHit(const render::CameraState& cam, uint32_t x, uint32_t y) {
    glm::vec3 o, d;
    render::primaryRay(cam, float(x), float(y), o, d);
    return o + d * (-o.y / d.y);
}

glm::vec3 project(const render::CameraState& cam, glm::vec3 p) {
    glm::vec4 c = cam.viewProj * glm::vec4(p, 1.0f);
    return glm::vec3(c) / c.w;  // x, y in [-1, 1] (y down), z reversed depth
}

}  // namespace

TEST(FrameRunner, DepthAndMotionMatchCpuGeometry) {
    gpu::Context ctx;
    Scene scene = floorScene();
    render::Renderer renderer(ctx, scene);
    const uint32_t w = 96, h = 64;
    app::FrameRunner runner(ctx, renderer, w, h);
    render::FrameInputs frame;
    frame.previousCamera = render::makeCamera({0.0f, 2.0f, 4.0f}, {0.0f, 0.0f, -2.0f}, {0, 1, 0}, 1.0f, w, h);
    frame.camera = render::makeCamera({0.4f, 2.1f, 3.7f}, {0.2f, 0.0f, -2.0f}, {0, 1, 0}, 1.0f, w, h);
    app::FrameResult result = runner.render(frame, {"depth", "motion"});
    const app::AovImage& depth = result.aovs.at("depth");
    const app::AovImage& motion = result.aovs.at("motion");
    ASSERT_EQ(depth.width, w);
    ASSERT_EQ(motion.height, h);

    int checked = 0;
    for (uint32_t y = h / 2 + 4; y < h; y += 5) {  // the lower half sees the floor
        for (uint32_t x = 3; x < w; x += 7) {
            glm::vec3 p = floorHit(frame.camera, x, y);
            glm::vec3 now = project(frame.camera, p);
            glm::vec3 before = project(frame.previousCamera, p);
            size_t i = (size_t(y) * w + x) * 4;
            EXPECT_NEAR(depth.rgba[i], now.z, 2e-5f * std::max(1.0f, now.z)) << x << "," << y;
            // Motion is in UV units (half the NDC difference); RG16F keeps about 3 digits.
            glm::vec2 expected = 0.5f * (glm::vec2(now) - glm::vec2(before));
            EXPECT_NEAR(motion.rgba[i + 0], expected.x, 2e-3f) << x << "," << y;
            EXPECT_NEAR(motion.rgba[i + 1], expected.y, 2e-3f) << x << "," << y;
            ++checked;
        }
    }
    EXPECT_GT(checked, 40);
    // The camera moved: motion must not be zero everywhere (a test that cannot pass on zeros).
    size_t centre = (size_t(h - 5) * w + w / 2) * 4;
    EXPECT_GT(std::abs(motion.rgba[centre]) + std::abs(motion.rgba[centre + 1]), 1e-3f);
}

TEST(FrameRunner, UnknownAovIsAnArgumentError) {
    gpu::Context ctx;
    Scene scene = floorScene();
    render::Renderer renderer(ctx, scene);
    app::FrameRunner runner(ctx, renderer, 16, 16);
    render::FrameInputs frame;
    frame.camera = frame.previousCamera = render::makeCamera({0, 2, 4}, {0, 0, 0}, {0, 1, 0}, 1.0f, 16, 16);
    try {
        runner.render(frame, {"sparkles"});
        FAIL() << "an unknown AOV was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadArguments);
    }
}
