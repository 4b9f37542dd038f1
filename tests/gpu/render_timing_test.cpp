// Not a test of speed (timings are never asserted): prints the renderer's pass timings on the
// gallery scene at 960x540. Run with --gtest_also_run_disabled_tests.
#include "render_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>

namespace speculum::render {
namespace {

TEST(RenderTiming, DISABLED_Gallery960x540) {
    gpu::Context ctx;
    Scene scene = loadScene(std::filesystem::path(SPECULUM_SOURCE_DIR) / "assets/scenes/gallery.gltf");
    Renderer renderer(ctx, scene);
    CameraState cam = scene.cameras.empty() ? frameBounds(scene, 960, 540)
                                            : makeCamera(scene.cameras[0], 960, 540);
    gpu::VulkanResourceAllocator allocator(ctx.physicalDevice(), ctx.device());
    gpu::VulkanFrameGraphExecutor executor(ctx.instance(), ctx.physicalDevice(), ctx.device(),
                                           ctx.timestampPeriodNs());
    std::map<std::string, std::vector<double>> ms;
    for (int frame = 0; frame < 12; ++frame) {
        FrameGraph fg(FrameGraphConfig{960, 540});
        FrameInputs inputs{cam, cam};
        GBuffer g = renderer.addGBufferPasses(fg, inputs);
        TextureHandle lit = renderer.addLightingPass(fg, inputs, g);
        fg.markOutput(renderer.addTonemapPass(fg, lit));
        fg.compile(allocator);
        ctx.submitAndWait([&](VkCommandBuffer cmd) { fg.execute(executor, cmd); });
        if (frame < 2) continue;  // warm-up
        for (const PassTiming& t : executor.readTimings()) ms[t.name].push_back(t.ms);
    }
    for (auto& [name, v] : ms) {
        std::sort(v.begin(), v.end());
        std::printf("%-20s median %.2f ms\n", name.c_str(), v[v.size() / 2]);
    }
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}

}  // namespace
}  // namespace speculum::render
