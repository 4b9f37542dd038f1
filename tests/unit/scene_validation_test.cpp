// Malformed scenes: each gives one Error(BadInput, "<file>: <problem>") and never a crash.
#include "scene_test_support.hpp"

#include "speculum/core.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <random>

using namespace speculum;
using namespace speculum::scenetest;

namespace {

// Loads `path` expecting BadInput; the message must name the file and contain `problem`.
void expectBadInput(const std::filesystem::path& path, const std::string& problem) {
    try {
        loadScene(path);
        ADD_FAILURE() << path << " loaded, expected an error containing '" << problem << "'";
    } catch (const Error& e) {
        std::string msg = e.what();
        EXPECT_EQ(e.code(), ExitCode::BadInput) << msg;
        EXPECT_NE(msg.find(path.filename().string()), std::string::npos) << msg;
        EXPECT_NE(msg.find(problem), std::string::npos) << "'" << problem << "' not in: " << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line please: " << msg;
    }
}

// Writes the quad with `edit` applied to its document and expects BadInput.
void expectBadEdit(const std::string& name, const std::function<void(json&)>& edit,
                   const std::string& problem) {
    auto dir = tmpDir("bad_edits");
    GltfData g = quad();
    edit(g.doc);
    expectBadInput(writeGltf(dir / (name + ".gltf"), g), problem);
}

std::filesystem::path badDir() { return tmpDir("bad_files"); }

}  // namespace

TEST(SceneValidation, MissingEmptyAndNotJson) {
    auto dir = badDir();
    expectBadInput(dir / "does_not_exist.gltf", "no such file");
    expectBadInput(writeText(dir / "empty.gltf", ""), "empty");
    expectBadInput(writeText(dir / "garbage.gltf", "{ \"asset\": nope"), "not valid JSON");
    expectBadInput(writeText(dir / "array.gltf", "[1, 2]"), "top level is an array");
    expectBadInput(writeText(dir / "noasset.gltf", "{\"nodes\": [{}]}"), "asset");
    expectBadInput(writeText(dir / "v1.gltf", R"({"asset": {"version": "1.0"}, "nodes": [{}]})"),
                   "unsupported glTF version");
}

TEST(SceneValidation, WrongJsonTypes) {
    expectBadEdit("nodes_number", [](json& d) { d["nodes"] = 5; }, "nodes: expected an array");
    expectBadEdit("mesh_string", [](json& d) { d["nodes"][1]["mesh"] = "x"; },
                  "nodes[1] \"Quad\".mesh: expected an integer, got a string");
    expectBadEdit("node_not_object", [](json& d) { d["nodes"][1] = 3; },
                  "nodes[1]: expected an object");
    expectBadEdit("translation_short", [](json& d) { d["nodes"][0]["translation"] = {1, 2}; },
                  "translation: expected 3 numbers");
    expectBadEdit("children_string", [](json& d) { d["nodes"][0]["children"] = {"a"}; },
                  "children[0]: expected an integer");
    expectBadEdit("count_string", [](json& d) { d["accessors"][0]["count"] = "4"; },
                  "accessors[0].count: expected an integer");
    expectBadEdit("attributes_array", [](json& d) {
        d["meshes"][0]["primitives"][0]["attributes"] = json::array(); }, "attributes");
    expectBadEdit("factor_string", [](json& d) {
        d["materials"][0]["pbrMetallicRoughness"] = {{"roughnessFactor", "rough"}}; },
                  "materials[0] \"Mat\".pbrMetallicRoughness.roughnessFactor");
    expectBadEdit("required_ext", [](json& d) {
        d["extensionsRequired"] = {"KHR_draco_mesh_compression"}; }, "KHR_draco_mesh_compression");
    expectBadEdit("light_type", [](json& d) {
        d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "laser"}}}; }, "laser");
}

TEST(SceneValidation, IndicesOutOfRange) {
    expectBadEdit("node_mesh", [](json& d) { d["nodes"][1]["mesh"] = 3; },
                  "mesh: index 3 out of range (the file has 1 meshes)");
    expectBadEdit("node_mesh_negative", [](json& d) { d["nodes"][1]["mesh"] = -1; },
                  "index -1 out of range");
    expectBadEdit("accessor", [](json& d) {
        d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99; }, "POSITION: index 99");
    expectBadEdit("indices_accessor", [](json& d) {
        d["meshes"][0]["primitives"][0]["indices"] = 42; }, "indices: index 42");
    expectBadEdit("buffer_view", [](json& d) { d["accessors"][0]["bufferView"] = 17; },
                  "accessors[0].bufferView: index 17");
    expectBadEdit("buffer", [](json& d) { d["bufferViews"][0]["buffer"] = 2; },
                  "bufferViews[0].buffer: index 2");
    expectBadEdit("material", [](json& d) { d["meshes"][0]["primitives"][0]["material"] = 9; },
                  "material: index 9");
    expectBadEdit("child", [](json& d) { d["nodes"][0]["children"] = {7}; },
                  "children[0]: index 7 out of range");
    expectBadEdit("scene_node", [](json& d) { d["scenes"][0]["nodes"] = {5}; },
                  "scenes[0].nodes[0]");
    expectBadEdit("scene", [](json& d) { d["scene"] = 1; }, "scene: index 1");
    expectBadEdit("texture", [](json& d) {
        d["materials"][0]["normalTexture"] = {{"index", 0}}; }, "normalTexture.index: index 0");
    expectBadEdit("light", [](json& d) {
        d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0; }, "light: index 0");
}

TEST(SceneValidation, IndexValuesBeyondVertexCount) {
    auto dir = badDir();
    QuadOptions o;
    o.indices = {0, 1, 2, 0, 2, 4};
    expectBadInput(writeGltf(dir / "index_value.gltf", quad(o)),
                   "index value 4 at position 5 is beyond the vertex count 4");
    o.indices = {0, 1, 2, 0};
    expectBadInput(writeGltf(dir / "index_count.gltf", quad(o)), "not a multiple of 3");
}

TEST(SceneValidation, ByteRangesBeyondBuffers) {
    expectBadEdit("accessor_range", [](json& d) { d["accessors"][0]["count"] = 100; },
                  "accessors[0]: needs 1200 bytes of buffer view 0, which has only 48");
    expectBadEdit("accessor_offset", [](json& d) { d["accessors"][0]["byteOffset"] = 4; },
                  "needs 52 bytes");
    expectBadEdit("view_range", [](json& d) { d["bufferViews"][0]["byteLength"] = 100000; },
                  "bufferViews[0]: byte range [0, 100000) is beyond the end of buffer 0");
    expectBadEdit("buffer_length", [](json& d) { d["buffers"][0]["byteLength"] = 400; },
                  "buffers[0]");
    expectBadEdit("stride", [](json& d) { d["bufferViews"][0]["byteStride"] = 6; }, "byteStride");
    expectBadEdit("absurd_count", [](json& d) { d["accessors"][0]["count"] = 300000000; },
                  "absurdly large");
    expectBadEdit("attr_type", [](json& d) { d["accessors"][0]["type"] = "VEC2"; },
                  "POSITION: accessor 0 has the wrong type");
    expectBadEdit("counts_differ", [](json& d) {
        d["accessors"][1]["count"] = 3; }, "attribute accessors differ in count");
}

TEST(SceneValidation, MissingBinFile) {
    auto dir = badDir();
    auto path = writeGltf(dir / "nobin.gltf", quad(), "nobin.bin");
    std::filesystem::remove(dir / "nobin.bin");
    expectBadInput(path, "buffers[0]: buffer file 'nobin.bin' is missing");
    writeText(dir / "short.bin", "abc");
    GltfData g = quad();
    g.doc["buffers"][0]["uri"] = "short.bin";
    expectBadInput(writeText(dir / "short.gltf", g.doc.dump()), "has 3 bytes");
    g.doc["buffers"][0].erase("uri");
    expectBadInput(writeText(dir / "nouri.gltf", g.doc.dump()), "no GLB BIN chunk");
}

TEST(SceneValidation, NonFinitePositions) {
    auto dir = badDir();
    QuadOptions o;
    o.positions[4] = std::numeric_limits<float>::quiet_NaN();
    expectBadInput(writeGltf(dir / "nan.gltf", quad(o)), "element 1 is not finite");
    o.positions[4] = 0.0f;
    o.positions[9] = std::numeric_limits<float>::infinity();
    expectBadInput(writeGlb(dir / "inf.glb", quad(o)), "element 3 is not finite");
    // JSON can only say "infinite" with an out-of-range literal.
    auto big = writeText(dir / "bigfactor.gltf",
                         R"({"asset":{"version":"2.0"},"nodes":[{"translation":[1e999,0,0]}]})");
    expectBadInput(big, "number overflow");
}

TEST(SceneValidation, TruncatedAndBrokenGlb) {
    auto dir = badDir();
    std::vector<uint8_t> glb = glbBytes(quad());
    std::vector<uint8_t> cut(glb.begin(), glb.begin() + long(glb.size() - 10));
    writeBytes(dir / "truncated.glb", cut);
    expectBadInput(dir / "truncated.glb", "truncated GLB");
    writeBytes(dir / "tiny.glb", {'g', 'l', 'T', 'F', 2, 0});
    expectBadInput(dir / "tiny.glb", "truncated GLB");
    writeText(dir / "notglb.glb", "hello there, not a glb");
    expectBadInput(dir / "notglb.glb", "not a GLB file");
    std::vector<uint8_t> v1 = glb;
    v1[4] = 1;
    writeBytes(dir / "version.glb", v1);
    expectBadInput(dir / "version.glb", "GLB version 1");
    // Every possible truncation fails cleanly (never a crash).
    for (size_t n = 0; n < glb.size(); n += 7) {
        writeBytes(dir / "cut.glb", std::vector<uint8_t>(glb.begin(), glb.begin() + long(n)));
        EXPECT_THROW(loadScene(dir / "cut.glb"), Error) << n;
    }
}

TEST(SceneValidation, NoNodes) {
    expectBadEdit("no_nodes", [](json& d) {
        d["nodes"] = json::array();
        d.erase("scenes");
        d.erase("scene"); }, "the scene has no nodes");
    expectBadEdit("scene_without_nodes", [](json& d) { d["scenes"][0]["nodes"] = json::array(); },
                  "scenes[0]: the scene has no nodes");
    expectBadEdit("nodes_absent", [](json& d) {
        d.erase("nodes");
        d.erase("scenes");
        d.erase("scene"); }, "the scene has no nodes");
}

TEST(SceneValidation, RecursiveNodes) {
    expectBadEdit("self_child", [](json& d) { d["nodes"][1]["children"] = {1}; },
                  "its own child");
    expectBadEdit("cycle", [](json& d) {
        d["nodes"].push_back({{"name", "C"}, {"children", {3}}});
        d["nodes"].push_back({{"name", "D"}, {"children", {2}}}); }, "own ancestor");
    expectBadEdit("cycle_through_root", [](json& d) { d["nodes"][1]["children"] = {0}; },
                  "own ancestor");
    expectBadEdit("two_parents", [](json& d) {
        d["nodes"].push_back({{"children", {1}}}); }, "only one parent");
}

TEST(SceneValidation, SpeculumExtensionValues) {
    auto refl = [](json v) {
        return [v](json& d) { d["materials"][0]["extensions"]["SPECULUM_reflections"] = v; };
    };
    auto probe = [](json v) {
        return [v](json& d) { d["nodes"][1]["extensions"]["SPECULUM_reflection_probe"] = v; };
    };
    const std::string m = "materials[0] \"Mat\".extensions.SPECULUM_reflections.";
    const std::string n = "nodes[1] \"Quad\".extensions.SPECULUM_reflection_probe.";
    expectBadEdit("refl_mode", refl({{"mode", "mirror"}}), m + "mode: unknown value \"mirror\"");
    expectBadEdit("refl_mode_type", refl({{"mode", 3}}), m + "mode: expected a string");
    expectBadEdit("refl_scale", refl({{"roughnessScale", -1}}), m + "roughnessScale");
    expectBadEdit("refl_override", refl({{"roughnessOverride", 2}}), m + "roughnessOverride");
    expectBadEdit("refl_max", refl({{"maxScreenSpaceRoughness", "high"}}),
                  m + "maxScreenSpaceRoughness: expected a number");
    expectBadEdit("refl_trace", refl({{"traceCmos", 1}}), m + "traceCmos: expected a boolean");
    expectBadEdit("refl_mirror", refl({{"mirrorForSelfReflections", "yes"}}),
                  m + "mirrorForSelfReflections");
    expectBadEdit("refl_not_object", refl(5), "SPECULUM_reflections: expected an object");
    expectBadEdit("probe_kind", probe({{"kind", "planer"}}), n + "kind: unknown value");
    // Planar probes (issue 24): two extents, both positive; an image height in [16, 4096].
    expectBadEdit("planar_extents_len", probe({{"kind", "planar"}, {"extents", {1, 1, 1}}}), n + "extents: expected 2");
    expectBadEdit("planar_extents_zero", probe({{"kind", "planar"}, {"extents", {2, 0}}}), n + "extents: every extent");
    expectBadEdit("planar_res_low", probe({{"kind", "planar"}, {"extents", {2, 2}}, {"resolution", 8}}),
                  n + "resolution: 8 is out of range [16, 4096]");
    expectBadEdit("planar_res_high", probe({{"kind", "planar"}, {"extents", {2, 2}}, {"resolution", 5000}}),
                  n + "resolution: 5000 is out of range");
    expectBadEdit("probe_shape", probe({{"shape", "cone"}}), n + "shape: unknown value");
    expectBadEdit("probe_extents", probe({{"extents", {1, -1, 1}}}), n + "extents");
    expectBadEdit("probe_extents_len", probe({{"extents", {1, 1}}}), n + "extents");
    expectBadEdit("probe_blend", probe({{"blendDistance", -0.5}}), n + "blendDistance");
    expectBadEdit("probe_res", probe({{"resolution", 0}}), n + "resolution");
    expectBadEdit("probe_res_float", probe({{"resolution", 64.5}}), n + "resolution");
    expectBadEdit("probe_res_not_pow2", probe({{"resolution", 100}}), n + "resolution");
    expectBadEdit("probe_update", probe({{"update", "sometimes"}}), n + "update");
    expectBadEdit("probe_order", probe({{"order", "first"}}), n + "order");
}

TEST(SceneValidation, RandomCorruptionNeverCrashes) {
    auto dir = badDir();
    std::vector<uint8_t> glb = glbBytes(quad());
    GltfData g = quad();
    g.doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(g.bin);
    std::string text = g.doc.dump();
    std::mt19937 rng(1234);
    for (int i = 0; i < 300; ++i) {
        bool binary = i % 2 == 0;
        std::vector<uint8_t> bytes = binary ? glb : std::vector<uint8_t>(text.begin(), text.end());
        for (int k = 0; k < 3; ++k) bytes[rng() % bytes.size()] = uint8_t(rng());
        auto path = dir / (binary ? "fuzz.glb" : "fuzz.gltf");
        writeBytes(path, bytes);
        try {
            loadScene(path);
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
        }
    }
}
