// extras.speculum_hidden_primary on a node (engine/scene/EXTENSIONS.md): read into
// Node::hiddenPrimary; anything but a boolean is a load error naming the node.
#include "scene_test_support.hpp"

#include "speculum/core.hpp"

#include <gtest/gtest.h>

namespace speculum::scenetest {
namespace {

// The quad with these extras on its two nodes (null: none), written as `file` and loaded.
Scene quadWithExtras(const std::string& file, const json& extras0, const json& extras1) {
    GltfData g = quad();
    if (!extras0.is_null()) g.doc["nodes"][0]["extras"] = extras0;
    if (!extras1.is_null()) g.doc["nodes"][1]["extras"] = extras1;
    return loadScene(writeGltf(tmpDir("hidden_primary") / file, g));
}

TEST(HiddenPrimaryExtras, ReadFromTheNode) {
    Scene scene = quadWithExtras("hidden.gltf", nullptr, {{"speculum_hidden_primary", true}, {"other", 1}});
    EXPECT_FALSE(scene.nodes[0].hiddenPrimary);
    EXPECT_TRUE(scene.nodes[1].hiddenPrimary);
}

TEST(HiddenPrimaryExtras, ExtrasOfAnyTypeStillLoad) {
    Scene scene = quadWithExtras("extras_any.gltf", 5, json::array({"speculum_hidden_primary", true}));
    EXPECT_FALSE(scene.nodes[0].hiddenPrimary);
    EXPECT_FALSE(scene.nodes[1].hiddenPrimary);
}

TEST(HiddenPrimaryExtras, SurvivesASave) {
    auto dir = tmpDir("hidden_primary");
    Scene scene = quadWithExtras("hidden_src.gltf", nullptr, {{"speculum_hidden_primary", true}});
    saveScene(scene, dir / "hidden_saved.gltf");
    Scene back = loadScene(dir / "hidden_saved.gltf");
    EXPECT_TRUE(back.nodes[1].hiddenPrimary);
    EXPECT_FALSE(back.nodes[0].hiddenPrimary);
}

TEST(HiddenPrimaryExtras, NotABooleanIsBadInput) {
    auto dir = tmpDir("hidden_primary");
    GltfData g = quad();
    g.doc["nodes"][1]["extras"] = {{"speculum_hidden_primary", "yes"}};
    try {
        loadScene(writeGltf(dir / "bad_hidden.gltf", g));
        FAIL() << "loaded";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("extras.speculum_hidden_primary"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bad_hidden.gltf"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace speculum::scenetest
