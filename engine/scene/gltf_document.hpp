// Internal to the scene layer: checked access to a glTF document and the validated, typed view
// of the parts that need buffer data (buffers, views, accessors, meshes, images). Everything here
// is checked before any byte of a buffer is read, so later stages can index without fear.
#pragma once

#include "speculum/core.hpp"
#include "speculum/scene.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace speculum::gltf {

using json = nlohmann::json;

// Hard limits against absurd sizes: a corrupt count must give a message, not a 100 GB allocation.
inline constexpr uint64_t kMaxAccessorCount = uint64_t(1) << 28;
inline constexpr uint64_t kMaxBufferBytes = uint64_t(1) << 32;
// Textures: 8192x8192 (2^26 pixels, 256 MB as RGBA8) at most. A 30-byte PNG header claiming
// 16384x16384 made stb_image allocate 1 GB before finding the data missing (issue 15).
inline constexpr uint64_t kMaxImagePixels = uint64_t(1) << 26;

// "meshes[2] \"Cube\"": how messages name an element of a top-level array.
std::string elementName(const char* array, size_t i, const json& obj);

// Every problem found through a Reader becomes one inputError naming the file and the JSON path
// of the offending value ("nodes[3] \"Lamp\".mesh: ...").
class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}
    const std::string& file() const { return file_; }
    [[noreturn]] void fail(const std::string& where, const std::string& problem) const;

    // Absent keys give nullptr (or the default); present keys of the wrong type fail.
    const json* object(const json& obj, const char* key, const std::string& where) const;
    const json* array(const json& obj, const char* key, const std::string& where) const;
    double number(const json& obj, const char* key, const std::string& where, double def) const;
    std::optional<double> optNumber(const json& obj, const char* key,
                                    const std::string& where) const;
    int64_t integer(const json& obj, const char* key, const std::string& where,
                    int64_t def) const;
    // An index into an array of `count` items; -1 when absent and not required.
    int index(const json& obj, const char* key, const std::string& where, size_t count,
              const char* what, bool required = false) const;
    std::string string(const json& obj, const char* key, const std::string& where,
                       const std::string& def = {}) const;
    bool boolean(const json& obj, const char* key, const std::string& where, bool def) const;
    // Exactly n finite numbers; `def` when absent.
    std::vector<float> floats(const json& obj, const char* key, const std::string& where,
                              size_t n, std::vector<float> def) const;

    // A top-level array of objects, or an empty array when absent.
    const json& topArray(const json& doc, const char* key) const;
    // f(element, where) for each element of the top-level array `key`, in order; `where` names
    // it for messages (elementName).
    template <typename F>
    void forEach(const json& doc, const char* key, F&& f) const {
        const json& items = topArray(doc, key);
        for (size_t i = 0; i < items.size(); ++i) f(items[i], elementName(key, i, items[i]));
    }

private:
    std::string file_;
};

const char* jsonTypeName(const json& v);

struct BufferInfo {
    uint64_t byteLength = 0;
    std::string uri;  // empty: the GLB BIN chunk
};

struct BufferViewInfo {
    int buffer = -1;
    uint64_t byteOffset = 0;
    uint64_t byteLength = 0;
    uint32_t byteStride = 0;  // 0: tightly packed
};

struct SparseInfo {
    uint32_t count = 0;
    int indicesView = -1;
    uint64_t indicesOffset = 0;
    uint32_t indicesComponentType = 0;
    int valuesView = -1;
    uint64_t valuesOffset = 0;
};

struct AccessorInfo {
    std::string where;
    int bufferView = -1;  // -1: all zeros (plus sparse values)
    uint64_t byteOffset = 0;
    uint32_t componentType = 0;
    bool normalized = false;
    uint32_t count = 0;
    int components = 1;
    std::optional<SparseInfo> sparse;
};

struct PrimitiveInfo {
    std::string where;
    int position = -1, normal = -1, tangent = -1, texcoord0 = -1, indices = -1;
    int material = -1;
    int mode = 4;
};

struct MeshInfo {
    std::string name;
    std::vector<PrimitiveInfo> primitives;
};

struct ImageInfo {
    std::string name;
    std::string uri;      // empty when the image lives in a buffer view
    int bufferView = -1;
};

// The validated structure of the document; scene-level objects (nodes, materials, lights,
// cameras) go straight into the Scene.
struct Document {
    std::vector<BufferInfo> buffers;
    std::vector<BufferViewInfo> bufferViews;
    std::vector<AccessorInfo> accessors;
    std::vector<MeshInfo> meshes;
    std::vector<int> textureSources;  // texture -> image, -1 when it has none we can use
    std::vector<ImageInfo> images;
    int sceneIndex = -1;              // the scene to show; -1 when the file has no scenes
    // KHR_lights_punctual and camera definitions, before they are placed by nodes.
    std::vector<Light> lights;
    std::vector<Camera> cameras;
    size_t materialCount = 0;
};

// The bytes of a .gltf/.glb file split into its JSON text and, for .glb, the BIN chunk.
struct Container {
    std::vector<uint8_t> bytes;  // the whole file (tinygltf re-reads the GLB from it)
    bool glb = false;
    std::string jsonText;
    bool hasBin = false;
    uint64_t binOffset = 0, binLength = 0;
};

Container readContainer(const std::filesystem::path& path, const Reader& r);
json parseJson(const std::string& text, const Reader& r);

// Validation of structure, types and indices (validate.cpp).
Document parseDocument(const json& doc, const Reader& r);
// Node hierarchy with cycle checks, probes, lights and cameras as declared (nodes.cpp).
void parseNodes(Scene& scene, const json& doc, const Document& d, const Reader& r);
// World transforms, flattened instances/lights/cameras and bounds (nodes.cpp).
void resolveScene(Scene& scene, const json& doc, const Document& d, const Reader& r);
void parseMaterials(Scene& scene, const json& doc, const Document& d, const Reader& r);

// Buffers and images through tinygltf (resources.cpp).
void loadResources(Scene& scene, const std::filesystem::path& path, const Container& c,
                   const Document& d, const Reader& r);
std::string percentDecode(const std::string& uri);
bool isDataUri(const std::string& uri);

// Mesh building from accessors (meshes.cpp) and tangent generation (tangents.cpp).
void buildMeshes(Scene& scene, const Document& d, const Reader& r);
void generateNormals(Primitive& p);
void generateTangents(Primitive& p);

// SPECULUM_* extensions (speculum_extensions.cpp).
MaterialReflections parseReflections(const json& ext, const std::string& where, const Reader& r);
ReflectionProbe parseProbe(const json& ext, const std::string& where, const Reader& r);
void writeReflections(json& ext, const MaterialReflections& m);
void writeProbe(json& ext, const ReflectionProbe& p);

// Saving (saver_files.cpp): all buffers merged into one (bufferViews rewritten), external images
// copied beside the new file, and the atomic write of .gltf+.bin or .glb.
std::vector<uint8_t> mergeBuffers(json& doc, const Scene& scene, const std::filesystem::path& path);
void copyExternalImages(json& doc, const Scene& scene, const std::filesystem::path& path);
void writeOutput(const json& doc, const std::vector<uint8_t>& bin,
                 const std::filesystem::path& path);

inline constexpr const char* kReflectionsExt = "SPECULUM_reflections";
inline constexpr const char* kProbeExt = "SPECULUM_reflection_probe";

}  // namespace speculum::gltf
