// The engine's scene: what a glTF file holds, in the form the renderer and the reference use.
// Loading validates everything (docs/design.md section 5, scenes); errors throw speculum::Error with
// ExitCode::BadInput and a message that names the file and the problem.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace speculum {

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec4 tangent;  // xyz tangent, w handedness; generated (MikkTSpace-like) when missing
    glm::vec2 uv;
};

struct Primitive {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;  // triangle list, always present (generated when absent)
    int material = -1;              // -1: the default material
    glm::vec3 boundsMin{0.0f};
    glm::vec3 boundsMax{0.0f};
};

struct Mesh {
    std::string name;
    std::vector<Primitive> primitives;
};

// Decoded texture image: RGBA8, straight from the file (colour space is the sampler's business).
struct Image {
    std::string name;    // uri or image name, for messages
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint8_t> rgba8;
    bool placeholder = false;  // true when the file was missing/unreadable and a default was used
};

struct TextureRef {
    int image = -1;  // index into Scene::images; -1: none
    int texCoord = 0;
    float scale = 1.0f;  // normal map scale
};

enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

enum class ReflectionMode : uint8_t { Off, ScreenSpace, ProbesOnly, LocalCubemapOnly };
// The extensions' names of each enum's values, in the enum's order (engine/scene/EXTENSIONS.md):
// the loader, the saver and the editor's fields all read these.
inline constexpr std::array<const char*, 4> kReflectionModeNames = {"off", "screen_space", "probes_only",
                                                                    "local_cubemap_only"};

// SPECULUM_reflections on a material.
struct MaterialReflections {
    ReflectionMode mode = ReflectionMode::ScreenSpace;
    float roughnessScale = 1.0f;
    std::optional<float> roughnessOverride;
    float maxScreenSpaceRoughness = 0.6f;
    bool traceCmos = true;
    bool mirrorForSelfReflections = false;
    friend bool operator==(const MaterialReflections&, const MaterialReflections&) = default;
};

struct Material {
    std::string name;
    glm::vec4 baseColor{1.0f};
    float metallic = 1.0f;
    float roughness = 1.0f;
    glm::vec3 emissive{0.0f};
    float emissiveStrength = 1.0f;  // KHR_materials_emissive_strength
    TextureRef baseColorTexture;
    TextureRef metallicRoughnessTexture;
    TextureRef normalTexture;
    TextureRef emissiveTexture;
    TextureRef occlusionTexture;  // scale holds the occlusion strength
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;  // AlphaMode::Mask only
    bool unlit = false;        // KHR_materials_unlit: output is base colour, exactly
    bool doubleSided = false;
    std::optional<MaterialReflections> reflections;  // SPECULUM_reflections
};

// Every lit material reflects (docs/design.md section 4, reflections): SPECULUM_reflections only tunes it or turns
// it off, so a plain glTF export's chrome reflects. Unlit materials never reflect. The renderer,
// the reflections module and the reference renderer all ask this one function.
MaterialReflections reflectionsOf(const Material& material);
bool reflects(const Material& material);

enum class LightType : uint8_t { Directional, Point, Spot };

struct Light {  // KHR_lights_punctual, resolved to world space
    std::string name;
    LightType type = LightType::Point;
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float range = 0.0f;  // 0: infinite
    float innerConeAngle = 0.0f;
    float outerConeAngle = 0.785398f;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // direction the light travels
};

struct Camera {  // resolved to world space
    std::string name;
    bool perspective = true;
    float yfov = 0.8f;        // radians
    float aspectRatio = 0.0f; // 0: use the viewport's
    float znear = 0.05f;
    float zfar = 0.0f;        // 0: infinite (the renderer uses reversed-Z, infinite far)
    float xmag = 1.0f, ymag = 1.0f;
    glm::mat4 world{1.0f};    // camera-to-world; looks down -Z, +Y up
};

enum class ProbeShape : uint8_t { Box, Sphere };
enum class ProbeKind : uint8_t { LocalCubemap, Cmo, Planar };
enum class ProbeUpdate : uint8_t { Once, OnDemand, EveryFrame, TimeSliced };
inline constexpr std::array<const char*, 2> kProbeShapeNames = {"box", "sphere"};
inline constexpr std::array<const char*, 3> kProbeKindNames = {"local_cubemap", "cmo", "planar"};
inline constexpr std::array<const char*, 4> kProbeUpdateNames = {"once", "on_demand", "every_frame", "time_sliced"};

// SPECULUM_reflection_probe on a node.
struct ReflectionProbe {
    ProbeKind kind = ProbeKind::LocalCubemap;
    ProbeShape shape = ProbeShape::Box;
    // Box half-extents, or radius in x for spheres; a planar probe's half width along the
    // node's local x and half depth along its local z in x and y (metres; z unused).
    glm::vec3 extents{1.0f};
    float blendDistance = 0.5f;
    // Cube face size; a planar probe's image height in pixels, 0 for its default (half the
    // view's height; the width follows the view's aspect).
    uint32_t resolution = 128;
    ProbeUpdate update = ProbeUpdate::Once;
    int order = 0;
    friend bool operator==(const ReflectionProbe&, const ReflectionProbe&) = default;
};

struct Node {
    std::string name;
    int parent = -1;
    std::vector<int> children;
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 scale{1.0f};
    // When the file gives a matrix instead of TRS. It wins over TRS for world and save; the TRS
    // fields then hold its decomposition, for display.
    std::optional<glm::mat4> matrix;
    int mesh = -1;
    int camera = -1;  // index into the glTF cameras
    int light = -1;   // index into the glTF lights
    std::optional<ReflectionProbe> probe;
    // extras.speculum_hidden_primary (EXTENSIONS.md): drawn into probe and CMO captures but not
    // into a view marked render::FrameInputs::primaryView (the game's collectibles).
    bool hiddenPrimary = false;
    glm::mat4 world{1.0f};  // resolved
};

// A node's transform relative to its parent: its matrix when the file gave one, else T * R * S.
glm::mat4 localMatrix(const Node& node);


// A mesh placed in the world: what the renderer draws.
struct Instance {
    int node = -1;
    int mesh = -1;
    glm::mat4 world{1.0f};
};

struct Scene {
    std::filesystem::path path;
    std::vector<Node> nodes;
    std::vector<int> roots;
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Image> images;
    std::vector<Instance> instances;  // flattened, world transforms applied
    std::vector<Light> lights;        // flattened to world space (one per light node)
    std::vector<Camera> cameras;      // flattened to world space (one per camera node), named by node or camera name
    glm::vec3 boundsMin{0.0f};        // world bounds of all instances
    glm::vec3 boundsMax{0.0f};
    // The original document, so that save() keeps what we did not understand.
    nlohmann::json document;
    // The glTF buffers' bytes as loaded (the .glb BIN chunk, .bin files, data: URIs), so that
    // saveScene writes a self-contained copy wherever it saves.
    std::vector<std::vector<uint8_t>> buffers;

    // nullptr when no camera has that name.
    const Camera* findCamera(const std::string& name) const;
};

// The nodes of the active scene (its roots and their descendants) that carry a probe of `kind`,
// in file order. A probe node outside the active scene does nothing, as a mesh, light or camera
// there does not (glTF 2.0, 3.5.2): before 2026-12-04 the probes module took every node's, so a
// CMO left out of scenes[].nodes still traced.
std::vector<int> activeProbeNodes(const Scene& scene, ProbeKind kind);

// Loads .gltf or .glb. Throws Error(ExitCode::BadInput, "<file>: <problem>"). Checks the limits
// of speculum/limits.hpp (JSON depth, expanded geometry, the environment map's header) first.
Scene loadScene(const std::filesystem::path& path);

// The environment map the scene names in scenes[i].extras.environment, resolved against the
// scene's folder; empty when it names none.
std::filesystem::path environmentPath(const Scene& scene);
// An equirect image's header before its pixels are read: a regular file (a device such as
// /dev/zero hung OpenImageIO's format probing), a format OpenImageIO reads, at most
// limits::kMaxEnvironmentSide a side and limits::kMaxEnvironmentPixels. Throws Error(BadInput)
// naming `file` with the numbers.
void checkEnvironmentImage(const std::filesystem::path& file);

// What the scene asks of the device: vertex and index buffers as the renderer lays them out
// (48-byte vertices, 32-bit indices) and textures as RGBA8 with full mip chains.
struct SceneBytes {
    uint64_t vertices = 0, indices = 0, textures = 0;
    uint64_t total() const { return vertices + indices + textures; }
};
SceneBytes sceneBytes(const Scene& scene);
// Writes .gltf (with a .bin beside it) or .glb; keeps unknown extensions and extras; writes the
// SPECULUM_* extensions from the typed structs. Writes to a temporary file, then renames.
void saveScene(const Scene& scene, const std::filesystem::path& path);

}  // namespace speculum
