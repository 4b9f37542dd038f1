// Scene loading: hierarchy, generated data, materials, lights, cameras and our extensions.
#include "scene_test_support.hpp"

#include "speculum/core.hpp"

#include <gtest/gtest.h>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include <glm/gtc/matrix_transform.hpp>

using namespace speculum;
using namespace speculum::scenetest;

namespace {

std::vector<uint8_t> pngBytes(int w, int h, const std::vector<uint8_t>& rgba) {
    std::vector<uint8_t> out;
    stbi_write_png_to_func(
        [](void* ctx, void* data, int size) {
            auto* v = static_cast<std::vector<uint8_t>*>(ctx);
            v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
        },
        &out, w, h, 4, rgba.data(), w * 4);
    return out;
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

glm::vec3 transformPoint(const glm::mat4& m, const glm::vec3& p) {
    return glm::vec3(m * glm::vec4(p, 1.0f));
}

}  // namespace

TEST(SceneLoad, QuadWithTrsHierarchyGivesWorldPositions) {
    auto dir = tmpDir("load_quad");
    Scene s = loadScene(writeGltf(dir / "quad.gltf", quad()));
    ASSERT_EQ(s.nodes.size(), 2u);
    EXPECT_EQ(s.nodes[1].parent, 0);
    EXPECT_EQ(s.roots, std::vector<int>{0});
    ASSERT_EQ(s.meshes.size(), 1u);
    ASSERT_EQ(s.meshes[0].primitives.size(), 1u);
    const Primitive& p = s.meshes[0].primitives[0];
    EXPECT_EQ(p.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(p.material, 0);
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.instances[0].node, 1);
    // Quad local (1,-1,0) -> rotate 90 about Z -> (1,1,0) -> +(0,0,1) -> *2 -> +(10,0,0).
    expectNear(transformPoint(s.instances[0].world, p.vertices[1].position), {12, 2, 2});
    expectNear(transformPoint(s.instances[0].world, p.vertices[3].position), {8, -2, 2});
    expectNear(s.boundsMin, {8, -2, 2});
    expectNear(s.boundsMax, {12, 2, 2});
    expectNear(p.boundsMin, {-1, -1, 0});
    // Normals rotate with the node: the file's +Z stays +Z under a rotation about Z.
    expectNear(glm::normalize(glm::mat3(s.instances[0].world) * p.vertices[0].normal), {0, 0, 1});
}

TEST(SceneLoad, MatrixNodeIsUsedAndDecomposed) {
    auto dir = tmpDir("load_matrix");
    GltfData g = quad();
    g.doc["nodes"][0].erase("translation");
    g.doc["nodes"][0].erase("scale");
    glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3)) *
                  glm::scale(glm::mat4(1.0f), glm::vec3(3.0f));
    json arr = json::array();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) arr.push_back(m[c][r]);
    g.doc["nodes"][0]["matrix"] = arr;
    Scene s = loadScene(writeGltf(dir / "m.gltf", g));
    ASSERT_TRUE(s.nodes[0].matrix.has_value());
    expectNear(s.nodes[0].translation, {1, 2, 3});
    expectNear(s.nodes[0].scale, {3, 3, 3});
    // (1,-1,0) -> (1,1,1) in the child, then *3 + (1,2,3).
    expectNear(transformPoint(s.instances[0].world, s.meshes[0].primitives[0].vertices[1].position),
               {4, 5, 6});
}

TEST(SceneLoad, NonIndexedPrimitiveGetsIndicesAndAreaWeightedNormals) {
    auto dir = tmpDir("load_nonindexed");
    QuadOptions o;
    o.indexed = false;
    o.normals = false;
    o.uvs = false;
    // Two triangles sharing nothing: one facing +Z, one facing +X.
    o.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1};
    Scene s = loadScene(writeGltf(dir / "n.gltf", quad(o)));
    const Primitive& p = s.meshes[0].primitives[0];
    EXPECT_EQ(p.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
    for (int i = 0; i < 3; ++i) expectNear(p.vertices[i].normal, {0, 0, 1});
    for (int i = 3; i < 6; ++i) expectNear(p.vertices[i].normal, {1, 0, 0});
    // Shared vertex between a big and a small face: the big one dominates.
    o.positions = {0, 0, 0, 4, 0, 0, 0, 4, 0, 0, 0.1f, 0, 0, 0, 0.1f};
    o.indexed = true;
    o.indices = {0, 1, 2, 0, 3, 4};
    Scene s2 = loadScene(writeGltf(dir / "n2.gltf", quad(o)));
    glm::vec3 n0 = s2.meshes[0].primitives[0].vertices[0].normal;
    EXPECT_NEAR(glm::length(n0), 1.0f, 1e-5f);
    EXPECT_GT(n0.z, 0.99f);
}

TEST(SceneLoad, IndicesOfEveryComponentType) {
    auto dir = tmpDir("load_indextypes");
    for (uint32_t type : {5121u, 5123u, 5125u}) {
        QuadOptions o;
        o.indexType = type;
        o.indices = {3, 2, 0, 2, 1, 0};
        Scene s = loadScene(writeGltf(dir / ("i" + std::to_string(type) + ".gltf"), quad(o)));
        EXPECT_EQ(s.meshes[0].primitives[0].indices, o.indices) << type;
    }
}

TEST(SceneLoad, TangentsAreGeneratedOrthogonalWithHandedness) {
    auto dir = tmpDir("load_tangents");
    // Standard layout: u grows along +X, the image's top (v = 0) is at +Y, so the normal map's
    // green axis (up the image) is +Y = cross(N, T): handedness +1.
    Scene s = loadScene(writeGltf(dir / "t.gltf", quad()));
    for (const Vertex& v : s.meshes[0].primitives[0].vertices) {
        EXPECT_NEAR(glm::dot(glm::vec3(v.tangent), v.normal), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-5f);
        expectNear(glm::vec3(v.tangent), {1, 0, 0});
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
    // Mirrored in U: tangent flips to -X, the bitangent still points up the image (+Y), so
    // cross(N, T) = -Y needs handedness -1.
    QuadOptions o;
    o.uvs2 = {1, 1, 0, 1, 0, 0, 1, 0};
    Scene m = loadScene(writeGltf(dir / "mirror.gltf", quad(o)));
    for (const Vertex& v : m.meshes[0].primitives[0].vertices) {
        expectNear(glm::vec3(v.tangent), {-1, 0, 0});
        EXPECT_EQ(v.tangent.w, -1.0f);
        glm::vec3 bitangent = glm::cross(v.normal, glm::vec3(v.tangent)) * v.tangent.w;
        expectNear(bitangent, {0, 1, 0});
    }
    // A tilted normal still gets an orthogonal tangent; no UVs still gives a valid frame.
    QuadOptions n;
    n.uvs = false;
    Scene nu = loadScene(writeGltf(dir / "nouv.gltf", quad(n)));
    for (const Vertex& v : nu.meshes[0].primitives[0].vertices) {
        EXPECT_NEAR(glm::dot(glm::vec3(v.tangent), v.normal), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-5f);
    }
}

TEST(SceneLoad, MaterialsUnlitFactorsAndTextures) {
    auto dir = tmpDir("load_materials");
    GltfData g = quad();
    std::vector<uint8_t> png = pngBytes(2, 1, {255, 0, 0, 255, 0, 0, 255, 128});
    int view = addView(g, png.data(), png.size());
    g.doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}},
                                   {{"bufferView", view}, {"mimeType", "image/png"}}});
    g.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
    g.doc["materials"] = json::array(
        {{{"name", "Flat"}, {"extensions", {{"KHR_materials_unlit", json::object()}}},
          {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 1}},
                                    {"baseColorTexture", {{"index", 0}}}}}},
         {{"name", "Shiny"},
          {"doubleSided", true},
          {"pbrMetallicRoughness", {{"metallicFactor", 0.2}, {"roughnessFactor", 0.3},
                                    {"metallicRoughnessTexture", {{"index", 1}}}}},
          {"normalTexture", {{"index", 1}, {"scale", 0.5}, {"texCoord", 0}}},
          {"emissiveFactor", {1, 0.5, 0}},
          {"emissiveTexture", {{"index", 0}}},
          {"alphaMode", "MASK"},
          {"alphaCutoff", 0.25},
          {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 7.5}}}}}}});
    Scene s = loadScene(writeGltf(dir / "mat.gltf", g));
    ASSERT_EQ(s.materials.size(), 2u);
    const Material& flat = s.materials[0];
    EXPECT_TRUE(flat.unlit);
    EXPECT_FALSE(flat.doubleSided);
    EXPECT_EQ(flat.baseColor, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
    EXPECT_EQ(flat.baseColorTexture.image, 0);
    EXPECT_EQ(flat.metallic, 1.0f);
    const Material& shiny = s.materials[1];
    EXPECT_FALSE(shiny.unlit);
    EXPECT_TRUE(shiny.doubleSided);
    EXPECT_FLOAT_EQ(shiny.metallic, 0.2f);
    EXPECT_FLOAT_EQ(shiny.roughness, 0.3f);
    EXPECT_EQ(shiny.metallicRoughnessTexture.image, 1);
    EXPECT_EQ(shiny.normalTexture.image, 1);
    EXPECT_FLOAT_EQ(shiny.normalTexture.scale, 0.5f);
    EXPECT_EQ(shiny.emissive, glm::vec3(1.0f, 0.5f, 0.0f));
    EXPECT_FLOAT_EQ(shiny.emissiveStrength, 7.5f);
    EXPECT_EQ(shiny.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(shiny.alphaCutoff, 0.25f);
    ASSERT_EQ(s.images.size(), 2u);
    for (const Image& im : s.images) {
        EXPECT_FALSE(im.placeholder);
        EXPECT_EQ(im.width, 2u);
        EXPECT_EQ(im.height, 1u);
        EXPECT_EQ(im.rgba8, (std::vector<uint8_t>{255, 0, 0, 255, 0, 0, 255, 128}));
    }
}

TEST(SceneLoad, MissingTextureWarnsAndUsesPlaceholder) {
    auto dir = tmpDir("load_missing_texture");
    GltfData g = quad();
    g.doc["images"] = json::array({{{"uri", "gone/missing%20file.png"}}, {{"uri", "bad.png"}}});
    g.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
    g.doc["materials"][0]["pbrMetallicRoughness"] = {{"baseColorTexture", {{"index", 0}}}};
    g.doc["materials"][0]["normalTexture"] = {{"index", 1}};
    writeText(dir / "bad.png", "this is not a png");
    int before = warningCount();
    Scene s;
    ASSERT_NO_THROW(s = loadScene(writeGltf(dir / "missing.gltf", g)));
    EXPECT_GE(warningCount(), before + 2);
    ASSERT_EQ(s.images.size(), 2u);
    for (const Image& im : s.images) {
        EXPECT_TRUE(im.placeholder);
        EXPECT_EQ(im.width, 1u);
        EXPECT_EQ(im.height, 1u);
        EXPECT_EQ(im.rgba8, (std::vector<uint8_t>{255, 255, 255, 255}));
    }
    EXPECT_EQ(s.materials[0].baseColorTexture.image, 0);
}

TEST(SceneLoad, ExternalImageFileIsDecoded) {
    auto dir = tmpDir("load_external_image");
    GltfData g = quad();
    std::filesystem::create_directories(dir / "tex");
    writeBytes(dir / "tex" / "a b.png", pngBytes(1, 1, {1, 2, 3, 4}));
    g.doc["images"] = json::array({{{"uri", "tex/a%20b.png"}}});
    Scene s = loadScene(writeGltf(dir / "ext.gltf", g));
    ASSERT_EQ(s.images.size(), 1u);
    EXPECT_FALSE(s.images[0].placeholder);
    EXPECT_EQ(s.images[0].rgba8, (std::vector<uint8_t>{1, 2, 3, 4}));
}

TEST(SceneLoad, LightsAndCamerasInWorldSpace) {
    auto dir = tmpDir("load_lights");
    GltfData g = quad();
    const float s = std::sqrt(0.5f);
    g.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
        {{{"name", "Sun"}, {"type", "directional"}, {"color", {1, 0.9, 0.8}}, {"intensity", 3}},
         {{"type", "point"}, {"range", 20}},
         {{"name", "Cone"},
          {"type", "spot"},
          {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}}});
    g.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    g.doc["cameras"] = json::array(
        {{{"name", "CamDef"}, {"type", "perspective"},
          {"perspective", {{"yfov", 0.9}, {"znear", 0.1}, {"aspectRatio", 1.5}}}},
         {{"name", "Ortho"}, {"type", "orthographic"},
          {"orthographic", {{"xmag", 2}, {"ymag", 3}, {"znear", 0.5}, {"zfar", 50}}}}});
    json& nodes = g.doc["nodes"];
    // Sun: rotated -90 degrees about X, so its -Z points down -Y.
    nodes.push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}},
                     {"rotation", {-s, 0, 0, s}}});
    nodes.push_back({{"name", "Bulb"}, {"translation", {1, 2, 3}},
                     {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    nodes.push_back({{"name", "Spot"}, {"translation", {0, 5, 0}}, {"rotation", {0, s, 0, s}},
                     {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    nodes.push_back({{"name", "MainCam"}, {"camera", 0}, {"translation", {0, 1, 5}}});
    nodes.push_back({{"camera", 1}, {"translation", {0, 0, 1}}});  // named by its camera
    nodes[0]["children"] = {1, 2, 3, 4, 5, 6};  // under Root: (10,0,0) and scale 2
    Scene sc = loadScene(writeGltf(dir / "lights.gltf", g));
    ASSERT_EQ(sc.lights.size(), 3u);
    const Light& sun = sc.lights[0];
    EXPECT_EQ(sun.name, "Sun");
    EXPECT_EQ(sun.type, LightType::Directional);
    EXPECT_FLOAT_EQ(sun.intensity, 3.0f);
    expectNear(sun.direction, {0, -1, 0});
    const Light& bulb = sc.lights[1];
    EXPECT_EQ(bulb.name, "Bulb");
    EXPECT_EQ(bulb.type, LightType::Point);
    EXPECT_FLOAT_EQ(bulb.range, 20.0f);
    expectNear(bulb.position, {12, 4, 6});
    const Light& spot = sc.lights[2];
    EXPECT_EQ(spot.name, "Spot");
    EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.2f);
    EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.5f);
    expectNear(spot.position, {10, 10, 0});
    expectNear(spot.direction, {-1, 0, 0});  // +90 about Y turns -Z into -X
    ASSERT_EQ(sc.cameras.size(), 2u);
    const Camera* main = sc.findCamera("MainCam");
    ASSERT_NE(main, nullptr);
    EXPECT_TRUE(main->perspective);
    EXPECT_FLOAT_EQ(main->yfov, 0.9f);
    EXPECT_FLOAT_EQ(main->aspectRatio, 1.5f);
    EXPECT_FLOAT_EQ(main->znear, 0.1f);
    EXPECT_EQ(main->zfar, 0.0f);
    expectNear(glm::vec3(main->world[3]), {10, 2, 10});
    // The node scale of 2 is not part of a camera's frame.
    EXPECT_NEAR(glm::length(glm::vec3(main->world[0])), 1.0f, 1e-5f);
    const Camera* ortho = sc.findCamera("Ortho");
    ASSERT_NE(ortho, nullptr);
    EXPECT_FALSE(ortho->perspective);
    EXPECT_FLOAT_EQ(ortho->xmag, 2.0f);
    EXPECT_FLOAT_EQ(ortho->ymag, 3.0f);
    EXPECT_FLOAT_EQ(ortho->zfar, 50.0f);
    EXPECT_EQ(sc.findCamera("CamDef"), nullptr);  // the node's name wins
    EXPECT_EQ(sc.findCamera("nope"), nullptr);
    EXPECT_EQ(sc.nodes[6].camera, 1);
    EXPECT_EQ(sc.nodes[3].light, 1);
}

TEST(SceneLoad, SpeculumExtensionsAreParsed) {
    auto dir = tmpDir("load_speculum_ext");
    GltfData g = quad();
    g.doc["extensionsUsed"] = {"SPECULUM_reflections", "SPECULUM_reflection_probe"};
    g.doc["materials"].push_back(
        {{"name", "Mirror"},
         {"extensions", {{"SPECULUM_reflections",
                          {{"mode", "local_cubemap_only"}, {"roughnessScale", 0.5},
                           {"roughnessOverride", 0.05}, {"maxScreenSpaceRoughness", 0.3},
                           {"traceCmos", false}, {"mirrorForSelfReflections", true}}}}}});
    g.doc["materials"].push_back(
        {{"name", "Defaults"}, {"extensions", {{"SPECULUM_reflections", json::object()}}}});
    g.doc["nodes"].push_back(
        {{"name", "Probe"},
         {"extensions", {{"SPECULUM_reflection_probe",
                          {{"kind", "cmo"}, {"shape", "sphere"}, {"extents", {3, 1, 1}},
                           {"blendDistance", 0.25}, {"resolution", 256},
                           {"update", "time_sliced"}, {"order", -2}}}}}});
    g.doc["scenes"][0]["nodes"] = {0, 2};
    Scene s = loadScene(writeGltf(dir / "ext.gltf", g));
    EXPECT_FALSE(s.materials[0].reflections.has_value());
    ASSERT_TRUE(s.materials[1].reflections.has_value());
    const MaterialReflections& r = *s.materials[1].reflections;
    EXPECT_EQ(r.mode, ReflectionMode::LocalCubemapOnly);
    EXPECT_FLOAT_EQ(r.roughnessScale, 0.5f);
    ASSERT_TRUE(r.roughnessOverride.has_value());
    EXPECT_FLOAT_EQ(*r.roughnessOverride, 0.05f);
    EXPECT_FLOAT_EQ(r.maxScreenSpaceRoughness, 0.3f);
    EXPECT_FALSE(r.traceCmos);
    EXPECT_TRUE(r.mirrorForSelfReflections);
    ASSERT_TRUE(s.materials[2].reflections.has_value());
    EXPECT_EQ(*s.materials[2].reflections, MaterialReflections{});
    ASSERT_TRUE(s.nodes[2].probe.has_value());
    const ReflectionProbe& p = *s.nodes[2].probe;
    EXPECT_EQ(p.kind, ProbeKind::Cmo);
    EXPECT_EQ(p.shape, ProbeShape::Sphere);
    EXPECT_EQ(p.extents, glm::vec3(3, 1, 1));
    EXPECT_FLOAT_EQ(p.blendDistance, 0.25f);
    EXPECT_EQ(p.resolution, 256u);
    EXPECT_EQ(p.update, ProbeUpdate::TimeSliced);
    EXPECT_EQ(p.order, -2);
    EXPECT_FALSE(s.nodes[0].probe.has_value());
    // A planar probe: its two extents, and resolution 0 (half the view's height) when absent.
    g.doc["nodes"][2]["extensions"]["SPECULUM_reflection_probe"] = {{"kind", "planar"}, {"extents", {2.5, 1.5}}};
    Scene planar = loadScene(writeGltf(dir / "planar.gltf", g));
    ASSERT_TRUE(planar.nodes[2].probe.has_value());
    EXPECT_EQ(planar.nodes[2].probe->kind, ProbeKind::Planar);
    EXPECT_FLOAT_EQ(planar.nodes[2].probe->extents.x, 2.5f);
    EXPECT_FLOAT_EQ(planar.nodes[2].probe->extents.y, 1.5f);
    EXPECT_EQ(planar.nodes[2].probe->resolution, 0u);
    EXPECT_EQ(s.roots, (std::vector<int>{0, 2}));
}

TEST(SceneLoad, OnlyTheActiveScenesProbesCount) {
    // A probe outside scenes[scene].nodes does nothing, as a mesh there does not; one under a
    // root node's children counts. Nodes: 0 the quad's root, 1 its mesh, then the probes.
    auto dir = tmpDir("load_active_probes");
    GltfData g = quad();
    g.doc["extensionsUsed"] = {"SPECULUM_reflection_probe"};
    auto cmo = [](const char* name) {
        return json{{"name", name},
                    {"extensions", {{"SPECULUM_reflection_probe", {{"kind", "cmo"}, {"resolution", 64}}}}}};
    };
    g.doc["nodes"].push_back(cmo("in_scene"));      // 2: a root of the scene
    g.doc["nodes"].push_back(cmo("left_out"));      // 3: a root of no scene
    g.doc["nodes"].push_back(cmo("child"));         // 4: a child of node 0
    g.doc["nodes"][0]["children"].push_back(4);
    g.doc["scenes"][0]["nodes"] = {0, 2};
    Scene s = loadScene(writeGltf(dir / "active.gltf", g));
    EXPECT_EQ(activeProbeNodes(s, ProbeKind::Cmo), (std::vector<int>{2, 4}));
    EXPECT_TRUE(activeProbeNodes(s, ProbeKind::Planar).empty());
    EXPECT_TRUE(s.nodes[3].probe.has_value());  // still loaded: the editor shows and saves it
}

TEST(SceneLoad, GlbWithBinChunk) {
    auto dir = tmpDir("load_glb");
    GltfData g = quad();
    std::vector<uint8_t> png = pngBytes(1, 1, {9, 8, 7, 255});
    int view = addView(g, png.data(), png.size());
    g.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
    Scene s = loadScene(writeGlb(dir / "quad.glb", g));
    ASSERT_EQ(s.instances.size(), 1u);
    expectNear(transformPoint(s.instances[0].world, s.meshes[0].primitives[0].vertices[1].position),
               {12, 2, 2});
    ASSERT_EQ(s.images.size(), 1u);
    EXPECT_EQ(s.images[0].rgba8, (std::vector<uint8_t>{9, 8, 7, 255}));
    ASSERT_EQ(s.buffers.size(), 1u);
}

TEST(SceneLoad, ExternalBinFileAndUnsupportedModesSkipped) {
    auto dir = tmpDir("load_bin");
    GltfData g = quad();
    json lines = g.doc["meshes"][0]["primitives"][0];
    lines["mode"] = 1;
    g.doc["meshes"][0]["primitives"].push_back(lines);
    int before = warningCount();
    Scene s = loadScene(writeGltf(dir / "quad.gltf", g, "quad data.bin"));
    EXPECT_EQ(s.meshes[0].primitives.size(), 1u);  // the line primitive is skipped...
    EXPECT_GT(warningCount(), before);              // ...with a warning
}

TEST(SceneLoad, TriangleStripsAndFansBecomeLists) {
    auto dir = tmpDir("load_strip");
    GltfData g = quad();
    g.doc["meshes"][0]["primitives"][0]["mode"] = 5;
    Scene s = loadScene(writeGltf(dir / "strip.gltf", g));
    EXPECT_EQ(s.meshes[0].primitives[0].indices,
              (std::vector<uint32_t>{0, 1, 2, 2, 1, 0, 2, 0, 2, 2, 0, 3}));
    g.doc["meshes"][0]["primitives"][0]["mode"] = 6;
    Scene f = loadScene(writeGltf(dir / "fan.gltf", g));
    EXPECT_EQ(f.meshes[0].primitives[0].indices.size(), 12u);
}

TEST(SceneLoad, SparseAccessorValuesAreApplied) {
    auto dir = tmpDir("load_sparse");
    GltfData g = quad();
    uint16_t which[] = {2};
    float value[] = {5, 6, 7};
    int iv = addView(g, which, sizeof(which));
    int vv = addView(g, value, sizeof(value));
    g.doc["accessors"][0]["sparse"] = {{"count", 1},
                                       {"indices", {{"bufferView", iv}, {"componentType", 5123}}},
                                       {"values", {{"bufferView", vv}}}};
    Scene s = loadScene(writeGltf(dir / "sparse.gltf", g));
    EXPECT_EQ(s.meshes[0].primitives[0].vertices[2].position, glm::vec3(5, 6, 7));
    EXPECT_EQ(s.meshes[0].primitives[0].vertices[1].position, glm::vec3(1, -1, 0));
}

TEST(SceneLoad, FindCamera) {
    Scene s;
    Camera a;
    a.name = "A";
    Camera b;
    b.name = "B";
    b.yfov = 1.2f;
    s.cameras = {a, b};
    ASSERT_NE(s.findCamera("B"), nullptr);
    EXPECT_FLOAT_EQ(s.findCamera("B")->yfov, 1.2f);
    EXPECT_EQ(s.findCamera("A"), &s.cameras[0]);
    EXPECT_EQ(s.findCamera("C"), nullptr);
    EXPECT_EQ(s.findCamera(""), nullptr);
}
