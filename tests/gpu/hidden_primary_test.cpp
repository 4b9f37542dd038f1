// Node::hiddenPrimary (extras.speculum_hidden_primary, the game's collectibles): absent from a
// primary view's depth and G-buffer, present in a probe face's capture (probes::faceCamera,
// FrameInputs as the probe module builds them), and Renderer::setNodeVisible removes a node from
// both.
#include "render_test_support.hpp"

#include "speculum/app/frame_runner.hpp"
#include "speculum/probes/probes.hpp"

namespace speculum::render::test {
namespace {

class HiddenPrimary : public SharedContextTest<HiddenPrimary> {};

// A wall at z = -5 and, node 1, a small square at z = -2 facing the origin.
Scene hiddenScene() {
    Scene scene;
    scene.nodes.resize(2);
    scene.nodes[0].name = "wall";
    scene.nodes[1].name = "collectible.0";
    scene.nodes[1].hiddenPrimary = true;
    scene.materials.push_back(Material{.name = "grey", .baseColor = glm::vec4(0.5f), .metallic = 0.0f});
    addMesh(scene, square({0, 0, -5}, {1, 0, 0}, {0, 1, 0}, 4.0f, 0));
    addMesh(scene, square({0, 0, -2}, {1, 0, 0}, {0, 1, 0}, 0.5f, 0));
    scene.instances[0].node = 0;
    scene.instances[1].node = 1;
    return scene;
}

// Reversed-Z depth of the centre pixel.
float centreDepth(app::FrameRunner& runner, const FrameInputs& frame) {
    app::FrameResult r = runner.render(frame, {"depth"});
    const app::AovImage& d = r.aovs.at("depth");
    return d.rgba[(size_t(d.height / 2) * d.width + d.width / 2) * 4];
}

TEST_F(HiddenPrimary, AbsentFromThePrimaryViewPresentInAProbeFace) {
    Scene scene = hiddenScene();
    Renderer renderer(*ctx_, scene);
    const uint32_t size = 32;
    app::FrameRunner runner(*ctx_, renderer, size, size);
    // Face 5 looks down -Z from the origin, as the probe capture sees it.
    FrameInputs probeFace;
    probeFace.camera = probeFace.previousCamera = probes::faceCamera(glm::vec3(0.0f), 5, size);
    FrameInputs primary = probeFace;
    primary.primaryView = true;
    const float znear = probeFace.camera.znear;
    // Reversed-Z with an infinite far plane: depth = znear / distance.
    const float atSquare = znear / 2.0f, atWall = znear / 5.0f;
    EXPECT_NEAR(centreDepth(runner, probeFace), atSquare, 1e-5f);
    EXPECT_NEAR(centreDepth(runner, primary), atWall, 1e-5f);
    // Nothing else changed: the wall is still there for both.
    renderer.setNodeVisible(1, false);
    EXPECT_NEAR(centreDepth(runner, probeFace), atWall, 1e-5f);
    EXPECT_NEAR(centreDepth(runner, primary), atWall, 1e-5f);
    renderer.setNodeVisible(1, true);
    EXPECT_NEAR(centreDepth(runner, probeFace), atSquare, 1e-5f);
}

TEST(HiddenPrimaryLoad, TheFlagComesFromNodeExtras) {
    Scene scene = loadScene(std::string(SPECULUM_SOURCE_DIR) + "/assets/scenes/hall_of_mirrors.gltf");
    int hidden = 0;
    for (const Node& n : scene.nodes) {
        EXPECT_EQ(n.hiddenPrimary, n.name.rfind("collectible.", 0) == 0) << n.name;
        hidden += n.hiddenPrimary;
    }
    EXPECT_EQ(hidden, 3);
}

}  // namespace
}  // namespace speculum::render::test
