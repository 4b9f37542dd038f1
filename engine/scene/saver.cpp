// saveScene: the original document is the base, so everything we do not model (unknown
// extensions, extras, animations, samplers...) survives; the typed structs overwrite only what
// they own. Files are written to a temporary name and renamed, so a failed save never leaves
// a half-written scene where the good one was.
#include "gltf_document.hpp"

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <set>

namespace speculum {

namespace {

using gltf::json;

[[noreturn]] void saveError(const std::filesystem::path& path, const std::string& problem) {
    throw Error(ExitCode::Failure, path.string() + ": cannot save: " + problem);
}

// The shortest decimal that reads back as the same float, so files stay readable (0.6, not
// 0.60000002384185791) and load -> save -> load is exact.
double num(float f) {
    char buf[64];
    auto res = std::to_chars(buf, buf + sizeof(buf), f);
    *res.ptr = '\0';
    return std::strtod(buf, nullptr);
}

json vec(std::initializer_list<float> v) {
    json a = json::array();
    for (float f : v) a.push_back(num(f));
    return a;
}

json& objectAt(json& parent, const char* key) {
    if (!parent.contains(key) || !parent[key].is_object()) parent[key] = json::object();
    return parent[key];
}

void eraseIfEmpty(json& parent, const char* key) {
    auto it = parent.find(key);
    if (it != parent.end() && it->empty()) parent.erase(it);
}

// Sets or removes an extension object on `owner`, keeping fields we do not model.
template <typename Write>
void setExtension(json& owner, const char* name, bool present, Write write) {
    if (present) {
        write(objectAt(objectAt(owner, "extensions"), name));
    } else if (owner.contains("extensions") && owner["extensions"].is_object()) {
        owner["extensions"].erase(name);
        eraseIfEmpty(owner, "extensions");
    }
}

void writeNode(json& j, const Node& n) {
    if (!n.name.empty()) j["name"] = n.name;
    for (const char* k : {"matrix", "translation", "rotation", "scale", "children"}) j.erase(k);
    if (n.matrix) {
        json m = json::array();
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m.push_back(num((*n.matrix)[c][r]));
        j["matrix"] = m;
    } else {
        if (n.translation != glm::vec3(0.0f))
            j["translation"] = vec({n.translation.x, n.translation.y, n.translation.z});
        if (n.rotation != glm::quat(1.0f, 0.0f, 0.0f, 0.0f))
            j["rotation"] = vec({n.rotation.x, n.rotation.y, n.rotation.z, n.rotation.w});
        if (n.scale != glm::vec3(1.0f)) j["scale"] = vec({n.scale.x, n.scale.y, n.scale.z});
    }
    if (!n.children.empty()) j["children"] = n.children;
    if (n.mesh >= 0) j["mesh"] = n.mesh;
    else j.erase("mesh");
    if (n.camera >= 0) j["camera"] = n.camera;
    else j.erase("camera");
    setExtension(j, "KHR_lights_punctual", n.light >= 0, [&](json& e) { e["light"] = n.light; });
    setExtension(j, gltf::kProbeExt, n.probe.has_value(),
                 [&](json& e) { gltf::writeProbe(e, *n.probe); });
}

void writeNodes(json& doc, const Scene& scene, const std::filesystem::path& path) {
    json& nodes = doc["nodes"];
    if (!nodes.is_array()) nodes = json::array();
    if (scene.nodes.size() < nodes.size())
        saveError(path, "nodes were removed from the scene; that is not supported");
    auto count = [&](const char* key) {
        return doc.contains(key) && doc[key].is_array() ? doc[key].size() : size_t(0);
    };
    size_t lights = 0;
    if (doc.contains("extensions") && doc["extensions"].is_object() &&
        doc["extensions"].contains("KHR_lights_punctual"))
        lights = doc["extensions"]["KHR_lights_punctual"].value("lights", json::array()).size();
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& n = scene.nodes[i];
        if (n.mesh >= int(count("meshes")) || n.camera >= int(count("cameras")) ||
            n.light >= int(lights))
            saveError(path, "node " + std::to_string(i) + " refers to a mesh, camera or light "
                                                          "the document does not have");
        if (i >= nodes.size()) nodes.push_back(json::object());
        writeNode(nodes[i], n);
    }
    // The active scene's roots follow the typed scene, so added root nodes are saved too.
    int active = doc.contains("scene") && doc["scene"].is_number_integer() ? doc["scene"].get<int>()
                                                                           : 0;
    if (!doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty())
        doc["scenes"] = json::array({json::object()});
    doc["scenes"][active]["nodes"] = scene.roots;
}

void writeMaterial(json& j, const Material& m) {
    if (!m.name.empty()) j["name"] = m.name;
    json& pbr = objectAt(j, "pbrMetallicRoughness");
    pbr["baseColorFactor"] = vec({m.baseColor.r, m.baseColor.g, m.baseColor.b, m.baseColor.a});
    pbr["metallicFactor"] = num(m.metallic);
    pbr["roughnessFactor"] = num(m.roughness);
    j["emissiveFactor"] = vec({m.emissive.r, m.emissive.g, m.emissive.b});
    if (j.contains("normalTexture") && j["normalTexture"].is_object())
        j["normalTexture"]["scale"] = num(m.normalTexture.scale);
    if (j.contains("occlusionTexture") && j["occlusionTexture"].is_object())
        j["occlusionTexture"]["strength"] = num(m.occlusionTexture.scale);
    static const char* const kAlpha[] = {"OPAQUE", "MASK", "BLEND"};
    j["alphaMode"] = kAlpha[int(m.alphaMode)];
    if (m.alphaMode == AlphaMode::Mask) j["alphaCutoff"] = num(m.alphaCutoff);
    else j.erase("alphaCutoff");
    j["doubleSided"] = m.doubleSided;
    setExtension(j, "KHR_materials_unlit", m.unlit, [](json&) {});
    setExtension(j, "KHR_materials_emissive_strength", m.emissiveStrength != 1.0f,
                 [&](json& e) { e["emissiveStrength"] = num(m.emissiveStrength); });
    setExtension(j, gltf::kReflectionsExt, m.reflections.has_value(),
                 [&](json& e) { gltf::writeReflections(e, *m.reflections); });
}

void writeMaterials(json& doc, const Scene& scene, const std::filesystem::path& path) {
    if (scene.materials.empty() && !doc.contains("materials")) return;
    json& mats = doc["materials"];
    if (!mats.is_array()) mats = json::array();
    if (scene.materials.size() < mats.size())
        saveError(path, "materials were removed from the scene; that is not supported");
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        if (i >= mats.size()) mats.push_back(json::object());
        writeMaterial(mats[i], scene.materials[i]);
    }
}

// extensionsUsed must name exactly the extensions in use among those whose use we control.
void writeExtensionsUsed(json& doc, const Scene& scene) {
    std::set<std::string> used;
    if (doc.contains("extensionsUsed") && doc["extensionsUsed"].is_array())
        for (const json& e : doc["extensionsUsed"])
            if (e.is_string()) used.insert(e.get<std::string>());
    auto manage = [&](const char* name, bool inUse) {
        if (inUse) used.insert(name);
        else used.erase(name);
    };
    bool unlit = false, strength = false, refl = false, probe = false, lights = false;
    for (const Material& m : scene.materials) {
        unlit |= m.unlit;
        strength |= m.emissiveStrength != 1.0f;
        refl |= m.reflections.has_value();
    }
    for (const Node& n : scene.nodes) {
        probe |= n.probe.has_value();
        lights |= n.light >= 0;
    }
    manage("KHR_materials_unlit", unlit);
    manage("KHR_materials_emissive_strength", strength);
    manage(gltf::kReflectionsExt, refl);
    manage(gltf::kProbeExt, probe);
    if (lights) used.insert("KHR_lights_punctual");  // light definitions may exist unused
    if (used.empty()) doc.erase("extensionsUsed");
    else doc["extensionsUsed"] = std::vector<std::string>(used.begin(), used.end());
}

}  // namespace

void saveScene(const Scene& scene, const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    if (ext != ".gltf" && ext != ".glb") saveError(path, "the file name must end in .gltf or .glb");
    if (!scene.document.is_object())
        saveError(path, "the scene has no glTF document (it was not loaded from a file)");
    json doc = scene.document;
    writeNodes(doc, scene, path);
    writeMaterials(doc, scene, path);
    writeExtensionsUsed(doc, scene);
    std::vector<uint8_t> bin = gltf::mergeBuffers(doc, scene, path);
    gltf::copyExternalImages(doc, scene, path);
    gltf::writeOutput(doc, bin, path);
}

}  // namespace speculum
