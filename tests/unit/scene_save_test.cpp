// Scene saving: round trips through .gltf and .glb keep what we model and what we do not.
#include "scene_test_support.hpp"

#include "speculum/core.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

using namespace speculum;
using namespace speculum::scenetest;

namespace {

// A scene exercising everything saveScene writes, plus things it must carry unchanged.
GltfData richScene() {
    GltfData g = quad();
    const float s = std::sqrt(0.5f);
    g.doc["extensionsUsed"] = {"KHR_lights_punctual", "SPECULUM_reflections",
                               "SPECULUM_reflection_probe", "VENDOR_unknown"};
    g.doc["extras"] = {{"author", "tests"}};
    g.doc["extensions"]["VENDOR_unknown"] = {{"answer", 42}};
    g.doc["extensions"]["KHR_lights_punctual"]["lights"] =
        json::array({{{"name", "Sun"}, {"type", "directional"}, {"intensity", 2}}});
    g.doc["cameras"] = json::array(
        {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.2}}}}});
    g.doc["materials"][0]["extras"] = {{"tag", "keep me"}};
    g.doc["materials"][0]["extensions"] = {
        {"SPECULUM_reflections", {{"mode", "probes_only"}, {"roughnessOverride", 0.1}}},
        {"VENDOR_unknown", {{"x", 1}}}};
    g.doc["materials"][0]["pbrMetallicRoughness"] = {{"baseColorFactor", {0.2, 0.4, 0.6, 1}},
                                                     {"roughnessFactor", 0.35}};
    g.doc["meshes"][0]["extras"] = {{"lod", 0}};
    g.doc["nodes"][1]["extras"] = {{"selectable", true}};
    g.doc["nodes"].push_back({{"name", "Sun"}, {"rotation", {-s, 0, 0, s}},
                              {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    g.doc["nodes"].push_back({{"name", "Cam"}, {"camera", 0}, {"translation", {0, 1, 4}}});
    g.doc["nodes"].push_back(
        {{"name", "Probe"},
         {"translation", {0, 1, 0}},
         {"extensions", {{"SPECULUM_reflection_probe",
                          {{"kind", "local_cubemap"}, {"extents", {2, 1, 3}}, {"order", 1}}},
                         {"VENDOR_unknown", {{"y", 2}}}}}});
    g.doc["scenes"][0]["nodes"] = {0, 2, 3, 4};
    g.doc["animations"] = json::array();  // unmodelled top-level data survives too
    g.doc["samplers"] = json::array({{{"magFilter", 9729}}});
    return g;
}

void expectSameScene(const Scene& a, const Scene& b) {
    ASSERT_EQ(a.meshes.size(), b.meshes.size());
    for (size_t m = 0; m < a.meshes.size(); ++m) {
        EXPECT_EQ(a.meshes[m].name, b.meshes[m].name);
        ASSERT_EQ(a.meshes[m].primitives.size(), b.meshes[m].primitives.size());
        for (size_t p = 0; p < a.meshes[m].primitives.size(); ++p) {
            const Primitive& pa = a.meshes[m].primitives[p];
            const Primitive& pb = b.meshes[m].primitives[p];
            EXPECT_EQ(pa.indices, pb.indices);
            EXPECT_EQ(pa.material, pb.material);
            ASSERT_EQ(pa.vertices.size(), pb.vertices.size());
            for (size_t v = 0; v < pa.vertices.size(); ++v) {
                EXPECT_EQ(pa.vertices[v].position, pb.vertices[v].position);
                EXPECT_EQ(pa.vertices[v].normal, pb.vertices[v].normal);
                EXPECT_EQ(pa.vertices[v].tangent, pb.vertices[v].tangent);
                EXPECT_EQ(pa.vertices[v].uv, pb.vertices[v].uv);
            }
        }
    }
    ASSERT_EQ(a.materials.size(), b.materials.size());
    for (size_t i = 0; i < a.materials.size(); ++i) {
        const Material& ma = a.materials[i];
        const Material& mb = b.materials[i];
        EXPECT_EQ(ma.name, mb.name);
        EXPECT_EQ(ma.baseColor, mb.baseColor);
        EXPECT_EQ(ma.metallic, mb.metallic);
        EXPECT_EQ(ma.roughness, mb.roughness);
        EXPECT_EQ(ma.emissive, mb.emissive);
        EXPECT_EQ(ma.emissiveStrength, mb.emissiveStrength);
        EXPECT_EQ(ma.unlit, mb.unlit);
        EXPECT_EQ(ma.doubleSided, mb.doubleSided);
        EXPECT_EQ(ma.reflections, mb.reflections);
        EXPECT_EQ(ma.baseColorTexture.image, mb.baseColorTexture.image);
    }
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        EXPECT_EQ(a.nodes[i].name, b.nodes[i].name);
        EXPECT_EQ(a.nodes[i].children, b.nodes[i].children);
        EXPECT_EQ(a.nodes[i].translation, b.nodes[i].translation);
        EXPECT_EQ(a.nodes[i].rotation, b.nodes[i].rotation);
        EXPECT_EQ(a.nodes[i].scale, b.nodes[i].scale);
        EXPECT_EQ(a.nodes[i].mesh, b.nodes[i].mesh);
        EXPECT_EQ(a.nodes[i].camera, b.nodes[i].camera);
        EXPECT_EQ(a.nodes[i].light, b.nodes[i].light);
        EXPECT_EQ(a.nodes[i].probe, b.nodes[i].probe);
        EXPECT_EQ(a.nodes[i].world, b.nodes[i].world);
    }
    EXPECT_EQ(a.roots, b.roots);
    ASSERT_EQ(a.lights.size(), b.lights.size());
    for (size_t i = 0; i < a.lights.size(); ++i) {
        EXPECT_EQ(a.lights[i].name, b.lights[i].name);
        EXPECT_EQ(a.lights[i].intensity, b.lights[i].intensity);
        EXPECT_EQ(a.lights[i].direction, b.lights[i].direction);
        EXPECT_EQ(a.lights[i].position, b.lights[i].position);
    }
    ASSERT_EQ(a.cameras.size(), b.cameras.size());
    for (size_t i = 0; i < a.cameras.size(); ++i) {
        EXPECT_EQ(a.cameras[i].name, b.cameras[i].name);
        EXPECT_EQ(a.cameras[i].yfov, b.cameras[i].yfov);
        EXPECT_EQ(a.cameras[i].world, b.cameras[i].world);
    }
    EXPECT_EQ(a.boundsMin, b.boundsMin);
    EXPECT_EQ(a.boundsMax, b.boundsMax);
}

void expectUnknownsKept(const json& doc) {
    EXPECT_EQ(doc["extras"]["author"], "tests");
    EXPECT_EQ(doc["extensions"]["VENDOR_unknown"]["answer"], 42);
    EXPECT_EQ(doc["materials"][0]["extras"]["tag"], "keep me");
    EXPECT_EQ(doc["materials"][0]["extensions"]["VENDOR_unknown"]["x"], 1);
    EXPECT_EQ(doc["meshes"][0]["extras"]["lod"], 0);
    EXPECT_EQ(doc["nodes"][1]["extras"]["selectable"], true);
    EXPECT_EQ(doc["nodes"][4]["extensions"]["VENDOR_unknown"]["y"], 2);
    EXPECT_EQ(doc["samplers"][0]["magFilter"], 9729);
    EXPECT_TRUE(doc.contains("animations"));
    const json& used = doc["extensionsUsed"];
    for (const char* e : {"VENDOR_unknown", "SPECULUM_reflections", "SPECULUM_reflection_probe",
                          "KHR_lights_punctual"})
        EXPECT_NE(std::find(used.begin(), used.end(), e), used.end()) << e;
}

bool noTempFiles(const std::filesystem::path& dir) {
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".tmp") return false;
    return true;
}

}  // namespace

TEST(SceneSave, GltfRoundTripKeepsSceneAndUnknowns) {
    auto dir = tmpDir("save_roundtrip");
    Scene a = loadScene(writeGltf(dir / "rich.gltf", richScene(), "rich.bin"));
    std::filesystem::create_directories(dir / "out");
    saveScene(a, dir / "out" / "copy.gltf");
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "copy.bin"));
    EXPECT_TRUE(noTempFiles(dir / "out"));
    // Self-contained: the original directory's .bin is not needed any more.
    std::filesystem::remove(dir / "rich.bin");
    Scene b = loadScene(dir / "out" / "copy.gltf");
    expectSameScene(a, b);
    expectUnknownsKept(b.document);
    // And a second generation is identical to the first.
    saveScene(b, dir / "out" / "again.gltf");
    Scene c = loadScene(dir / "out" / "again.gltf");
    expectSameScene(b, c);
    json db = b.document, dc = c.document;
    db["buffers"][0].erase("uri");
    dc["buffers"][0].erase("uri");
    EXPECT_EQ(db, dc);
}

// Saving a .gltf over itself with the same geometry leaves its .bin alone (the same file, not
// replaced by a rename), so the save is one atomic rename of the document; different bytes are
// written.
TEST(SceneSave, GltfSaveOverItselfRewritesTheBinOnlyWhenItChanges) {
    auto dir = tmpDir("save_bin_kept");
    Scene a = loadScene(writeGltf(dir / "rich.gltf", richScene(), "rich.bin"));
    std::filesystem::create_directories(dir / "out");
    const auto path = dir / "out" / "scene.gltf", bin = dir / "out" / "scene.bin";
    saveScene(a, path);
    struct stat before {};
    ASSERT_EQ(stat(bin.c_str(), &before), 0);
    Scene b = loadScene(path);
    b.nodes[0].name = "renamed";  // an edit of the document only
    saveScene(b, path);
    struct stat after {};
    ASSERT_EQ(stat(bin.c_str(), &after), 0);
    EXPECT_EQ(before.st_ino, after.st_ino) << "the unchanged .bin was written again";
    EXPECT_EQ(loadScene(path).nodes[0].name, "renamed");
    EXPECT_TRUE(noTempFiles(dir / "out"));
    // A different buffer is written.
    Scene c = loadScene(path);
    ASSERT_FALSE(c.buffers.empty());
    ASSERT_FALSE(c.buffers[0].empty());
    c.buffers[0][0] ^= 0xff;
    saveScene(c, path);
    struct stat changed {};
    ASSERT_EQ(stat(bin.c_str(), &changed), 0);
    EXPECT_NE(before.st_ino, changed.st_ino);
    EXPECT_EQ(loadScene(path).buffers[0][0], c.buffers[0][0]);
}

TEST(SceneSave, GlbRoundTripBothWays) {
    auto dir = tmpDir("save_glb");
    Scene a = loadScene(writeGltf(dir / "rich.gltf", richScene()));
    saveScene(a, dir / "rich.glb");
    EXPECT_TRUE(noTempFiles(dir));
    Scene b = loadScene(dir / "rich.glb");
    expectSameScene(a, b);
    expectUnknownsKept(b.document);
    EXPECT_FALSE(b.document["buffers"][0].contains("uri"));
    saveScene(b, dir / "back.gltf");
    Scene c = loadScene(dir / "back.gltf");
    expectSameScene(a, c);
    expectUnknownsKept(c.document);
    // A .glb loaded and saved over itself stays loadable.
    Scene g = loadScene(writeGlb(dir / "quad.glb", quad()));
    saveScene(g, dir / "quad.glb");
    expectSameScene(g, loadScene(dir / "quad.glb"));
}

TEST(SceneSave, TypedChangesAreWrittenAndExtensionsUsedFollows) {
    auto dir = tmpDir("save_changes");
    Scene a = loadScene(writeGltf(dir / "rich.gltf", richScene()));
    a.nodes[1].translation = {5, 6, 7};
    a.nodes[0].matrix = glm::mat4(2.0f);
    a.nodes[0].matrix->operator[](3) = glm::vec4(1, 2, 3, 1);
    a.materials[0].roughness = 0.75f;
    a.materials[0].baseColor = {1, 0, 0, 0.5f};
    a.materials[0].unlit = true;
    a.materials[0].emissiveStrength = 4.0f;
    a.materials[0].reflections.reset();
    a.nodes[4].probe.reset();
    ReflectionProbe probe;
    probe.shape = ProbeShape::Sphere;
    probe.update = ProbeUpdate::EveryFrame;
    a.nodes[2].probe = probe;
    // A planar probe keeps its two extents and its default resolution (0: written as absent).
    ReflectionProbe planar;
    planar.kind = ProbeKind::Planar;
    planar.extents = {2.0f, 1.5f, 1.0f};
    planar.resolution = 0;
    a.nodes[3].probe = planar;
    saveScene(a, dir / "changed.gltf");
    Scene b = loadScene(dir / "changed.gltf");
    EXPECT_EQ(b.nodes[1].translation, glm::vec3(5, 6, 7));
    ASSERT_TRUE(b.nodes[0].matrix.has_value());
    EXPECT_EQ(*b.nodes[0].matrix, *a.nodes[0].matrix);
    EXPECT_EQ(b.materials[0].roughness, 0.75f);
    EXPECT_EQ(b.materials[0].baseColor, glm::vec4(1, 0, 0, 0.5f));
    EXPECT_TRUE(b.materials[0].unlit);
    EXPECT_EQ(b.materials[0].emissiveStrength, 4.0f);
    EXPECT_FALSE(b.materials[0].reflections.has_value());
    EXPECT_FALSE(b.nodes[4].probe.has_value());
    ASSERT_TRUE(b.nodes[2].probe.has_value());
    EXPECT_EQ(*b.nodes[2].probe, probe);
    ASSERT_TRUE(b.nodes[3].probe.has_value());
    EXPECT_EQ(*b.nodes[3].probe, planar);
    EXPECT_FALSE(b.document["nodes"][3]["extensions"]["SPECULUM_reflection_probe"].contains("resolution"));
    EXPECT_EQ(b.document["nodes"][3]["extensions"]["SPECULUM_reflection_probe"]["extents"].size(), 2u);
    const json& used = b.document["extensionsUsed"];
    auto has = [&](const char* e) { return std::find(used.begin(), used.end(), e) != used.end(); };
    EXPECT_FALSE(has("SPECULUM_reflections"));
    EXPECT_TRUE(has("SPECULUM_reflection_probe"));
    EXPECT_TRUE(has("KHR_materials_unlit"));
    EXPECT_TRUE(has("KHR_materials_emissive_strength"));
    EXPECT_TRUE(has("VENDOR_unknown"));
    // Unknown fields beside ours survive even when our extension object is removed.
    EXPECT_EQ(b.document["materials"][0]["extensions"]["VENDOR_unknown"]["x"], 1);
    EXPECT_FALSE(b.document["materials"][0]["extensions"].contains("SPECULUM_reflections"));
    EXPECT_EQ(b.document["nodes"][4]["extensions"]["VENDOR_unknown"]["y"], 2);
}

TEST(SceneSave, ExternalImagesAreCopiedAlong) {
    auto dir = tmpDir("save_images");
    GltfData g = quad();
    std::filesystem::create_directories(dir / "src" / "tex");
    // Not a decodable image: the copy must be byte-for-byte, whatever the content.
    writeText(dir / "src" / "tex" / "albedo.png", "png bytes");
    g.doc["images"] = json::array({{{"uri", "tex/albedo.png"}}});
    Scene a = loadScene(writeGltf(dir / "src" / "s.gltf", g));
    std::filesystem::create_directories(dir / "dst");
    saveScene(a, dir / "dst" / "s.glb");
    EXPECT_TRUE(std::filesystem::exists(dir / "dst" / "tex" / "albedo.png"));
}

TEST(SceneSave, RejectsBadTargets) {
    auto dir = tmpDir("save_bad");
    Scene a = loadScene(writeGltf(dir / "q.gltf", quad()));
    EXPECT_THROW(saveScene(a, dir / "q.obj"), Error);
    EXPECT_THROW(saveScene(a, dir / "no_such_dir" / "q.gltf"), Error);
    EXPECT_TRUE(std::filesystem::exists(dir / "q.gltf"));
    Scene empty;
    EXPECT_THROW(saveScene(empty, dir / "e.gltf"), Error);
    a.nodes[1].mesh = 5;  // no such mesh in the document
    EXPECT_THROW(saveScene(a, dir / "q.gltf"), Error);
    EXPECT_NO_THROW(loadScene(dir / "q.gltf"));  // the original is untouched
}
