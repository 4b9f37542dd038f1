// Builders for the small glTF files the Scene* tests write at run time into SPECULUM_TEST_TMP.
#pragma once

#include "speculum/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

namespace speculum::scenetest {

using json = nlohmann::json;

struct QuadOptions {
    bool normals = true;
    bool uvs = true;
    bool indexed = true;
    uint32_t indexType = 5123;  // unsigned short
    std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
    // Corners counter-clockwise from -x-y, seen from +Z.
    std::vector<float> positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    // glTF V runs down the image: the top edge (y = +1) has v = 0.
    std::vector<float> uvs2 = {0, 1, 1, 1, 1, 0, 0, 0};
};

struct GltfData {
    json doc;
    std::vector<uint8_t> bin;
};

// ctest runs tests in parallel processes: each test gets a folder of its own so that two tests
// using the same sub-folder name never delete each other's files.
inline std::filesystem::path tmpDir(const std::string& sub) {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string owner = test ? std::string(test->test_suite_name()) + "." + test->name() : "no_test";
    std::filesystem::path dir = std::filesystem::path(SPECULUM_TEST_TMP) / "scene" / owner / sub;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string base64(const std::vector<uint8_t>& data) {
    static const char* const kChars =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < data.size(); i += 3) {
        uint32_t v = data[i] << 16 | data[i + 1] << 8 | data[i + 2];
        for (int k = 3; k >= 0; --k) out += kChars[(v >> (6 * k)) & 63];
    }
    if (i + 1 == data.size()) {
        uint32_t v = data[i] << 16;
        out += std::string{kChars[v >> 18], kChars[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == data.size()) {
        uint32_t v = data[i] << 16 | data[i + 1] << 8;
        out += std::string{kChars[v >> 18], kChars[(v >> 12) & 63], kChars[(v >> 6) & 63], '='};
    }
    return out;
}

// Appends bytes as a new buffer view (4-byte aligned) and returns the view index.
inline int addView(GltfData& g, const void* data, size_t size) {
    g.bin.resize((g.bin.size() + 3) & ~size_t(3), 0);
    size_t offset = g.bin.size();
    g.bin.resize(offset + size);
    std::memcpy(g.bin.data() + offset, data, size);
    g.doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}});
    g.doc["buffers"] = json::array({{{"byteLength", g.bin.size()}}});
    return int(g.doc["bufferViews"].size() - 1);
}

inline int addAccessor(GltfData& g, const std::vector<float>& v, const char* type, int comps) {
    int view = addView(g, v.data(), v.size() * 4);
    g.doc["accessors"].push_back({{"bufferView", view}, {"componentType", 5126},
                                  {"count", v.size() / comps}, {"type", type}});
    return int(g.doc["accessors"].size() - 1);
}

inline int addIndices(GltfData& g, const std::vector<uint32_t>& idx, uint32_t type) {
    std::vector<uint8_t> bytes;
    for (uint32_t i : idx) {
        size_t size = type == 5121 ? 1 : type == 5123 ? 2 : 4;
        for (size_t b = 0; b < size; ++b) bytes.push_back(uint8_t(i >> (8 * b)));
    }
    int view = addView(g, bytes.data(), bytes.size());
    g.doc["accessors"].push_back({{"bufferView", view}, {"componentType", type},
                                  {"count", idx.size()}, {"type", "SCALAR"}});
    return int(g.doc["accessors"].size() - 1);
}

// Root "Root" (translation (10,0,0), uniform scale 2) with child "Quad" (90 degrees about +Z,
// translation (0,0,1)) holding mesh 0, material 0.
inline GltfData quad(const QuadOptions& o = {}) {
    GltfData g;
    g.doc = {{"asset", {{"version", "2.0"}, {"generator", "speculum scene tests"}}},
             {"scene", 0},
             {"scenes", json::array({{{"nodes", {0}}}})},
             {"bufferViews", json::array()},
             {"accessors", json::array()},
             {"materials", json::array({{{"name", "Mat"}}})}};
    json attrs;
    attrs["POSITION"] = addAccessor(g, o.positions, "VEC3", 3);
    size_t n = o.positions.size() / 3;
    if (o.normals) {
        std::vector<float> nrm;
        for (size_t i = 0; i < n; ++i) nrm.insert(nrm.end(), {0, 0, 1});
        attrs["NORMAL"] = addAccessor(g, nrm, "VEC3", 3);
    }
    if (o.uvs) attrs["TEXCOORD_0"] = addAccessor(g, o.uvs2, "VEC2", 2);
    json prim = {{"attributes", attrs}, {"material", 0}};
    if (o.indexed) prim["indices"] = addIndices(g, o.indices, o.indexType);
    g.doc["meshes"] = json::array({{{"name", "QuadMesh"}, {"primitives", {prim}}}});
    const float s = std::sqrt(0.5f);
    g.doc["nodes"] = json::array(
        {{{"name", "Root"}, {"translation", {10, 0, 0}}, {"scale", {2, 2, 2}}, {"children", {1}}},
         {{"name", "Quad"}, {"mesh", 0}, {"translation", {0, 0, 1}}, {"rotation", {0, 0, s, s}}}});
    return g;
}

inline std::filesystem::path writeText(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

inline void writeBytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// .gltf with the buffer as a data: URI, or as a .bin file beside it when binName is given.
inline std::filesystem::path writeGltf(const std::filesystem::path& path, GltfData g,
                                const std::string& binName = {}) {
    if (!g.bin.empty()) {
        if (binName.empty()) {
            g.doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(g.bin);
        } else {
            g.doc["buffers"][0]["uri"] = binName;
            writeBytes(path.parent_path() / binName, g.bin);
        }
    }
    return writeText(path, g.doc.dump(1));
}

inline std::vector<uint8_t> glbBytes(const GltfData& g) {
    std::string text = g.doc.dump();
    text.resize((text.size() + 3) & ~size_t(3), ' ');
    std::vector<uint8_t> bin = g.bin;
    bin.resize((bin.size() + 3) & ~size_t(3), 0);
    auto u32 = [](std::vector<uint8_t>& out, uint32_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
    };
    std::vector<uint8_t> out = {'g', 'l', 'T', 'F'};
    u32(out, 2);
    u32(out, uint32_t(12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size())));
    u32(out, uint32_t(text.size()));
    u32(out, 0x4E4F534Au);
    out.insert(out.end(), text.begin(), text.end());
    if (!bin.empty()) {
        u32(out, uint32_t(bin.size()));
        u32(out, 0x004E4942u);
        out.insert(out.end(), bin.begin(), bin.end());
    }
    return out;
}

inline std::filesystem::path writeGlb(const std::filesystem::path& path, const GltfData& g) {
    writeBytes(path, glbBytes(g));
    return path;
}

}  // namespace speculum::scenetest
