// Materials: pbrMetallicRoughness, normal/occlusion/emissive maps, alpha, and the extensions we
// understand (unlit, emissive strength, SPECULUM_reflections).
#include "gltf_document.hpp"

namespace speculum::gltf {

namespace {

TextureRef parseTextureRef(const json& m, const char* key, const std::string& where,
                           const Document& d, const Reader& r, const char* scaleKey) {
    TextureRef ref;
    const json* t = r.object(m, key, where);
    if (!t) return ref;
    std::string tw = where + "." + key;
    int texture = r.index(*t, "index", tw, d.textureSources.size(), "textures", true);
    ref.image = d.textureSources[texture];
    if (ref.image < 0)
        logWarning(r.file() + ": " + tw + ": texture " + std::to_string(texture) +
                   " has no image source we can read; ignored");
    int64_t texCoord = r.integer(*t, "texCoord", tw, 0);
    if (texCoord < 0 || texCoord > 7) r.fail(tw + ".texCoord", "out of range [0, 7]");
    ref.texCoord = int(texCoord);
    if (scaleKey) ref.scale = float(r.number(*t, scaleKey, tw, 1.0));
    return ref;
}

void parsePbr(Material& mat, const json& m, const std::string& where, const Document& d,
              const Reader& r) {
    const json* pbr = r.object(m, "pbrMetallicRoughness", where);
    if (!pbr) return;
    std::string pw = where + ".pbrMetallicRoughness";
    auto c = r.floats(*pbr, "baseColorFactor", pw, 4, {1, 1, 1, 1});
    mat.baseColor = {c[0], c[1], c[2], c[3]};
    mat.metallic = float(r.number(*pbr, "metallicFactor", pw, 1.0));
    mat.roughness = float(r.number(*pbr, "roughnessFactor", pw, 1.0));
    for (float v : c)
        if (v < 0.0f || v > 1.0f) r.fail(pw + ".baseColorFactor", "components must be in [0, 1]");
    if (mat.metallic < 0 || mat.metallic > 1) r.fail(pw + ".metallicFactor", "not in [0, 1]");
    if (mat.roughness < 0 || mat.roughness > 1) r.fail(pw + ".roughnessFactor", "not in [0, 1]");
    mat.baseColorTexture = parseTextureRef(*pbr, "baseColorTexture", pw, d, r, nullptr);
    mat.metallicRoughnessTexture =
        parseTextureRef(*pbr, "metallicRoughnessTexture", pw, d, r, nullptr);
}

void parseExtensions(Material& mat, const json& m, const std::string& where, const Reader& r) {
    const json* exts = r.object(m, "extensions", where);
    if (!exts) return;
    std::string ew = where + ".extensions";
    mat.unlit = r.object(*exts, "KHR_materials_unlit", ew) != nullptr;
    if (const json* es = r.object(*exts, "KHR_materials_emissive_strength", ew)) {
        mat.emissiveStrength = float(
            r.number(*es, "emissiveStrength", ew + ".KHR_materials_emissive_strength", 1.0));
        if (mat.emissiveStrength < 0)
            r.fail(ew + ".KHR_materials_emissive_strength.emissiveStrength", "negative");
    }
    if (const json* refl = r.object(*exts, kReflectionsExt, ew))
        mat.reflections = parseReflections(*refl, ew + "." + kReflectionsExt, r);
}

Material parseMaterial(const json& m, const std::string& where, const Document& d,
                       const Reader& r) {
    Material mat;
    mat.name = r.string(m, "name", where);
    parsePbr(mat, m, where, d, r);
    mat.normalTexture = parseTextureRef(m, "normalTexture", where, d, r, "scale");
    mat.occlusionTexture = parseTextureRef(m, "occlusionTexture", where, d, r, "strength");
    mat.emissiveTexture = parseTextureRef(m, "emissiveTexture", where, d, r, nullptr);
    auto e = r.floats(m, "emissiveFactor", where, 3, {0, 0, 0});
    mat.emissive = {e[0], e[1], e[2]};
    std::string alpha = r.string(m, "alphaMode", where, "OPAQUE");
    if (alpha == "OPAQUE") mat.alphaMode = AlphaMode::Opaque;
    else if (alpha == "MASK") mat.alphaMode = AlphaMode::Mask;
    else if (alpha == "BLEND") mat.alphaMode = AlphaMode::Blend;
    else r.fail(where + ".alphaMode", "\"" + alpha + "\" is not OPAQUE, MASK or BLEND");
    mat.alphaCutoff = float(r.number(m, "alphaCutoff", where, 0.5));
    if (mat.alphaCutoff < 0) r.fail(where + ".alphaCutoff", "negative");
    mat.doubleSided = r.boolean(m, "doubleSided", where, false);
    parseExtensions(mat, m, where, r);
    return mat;
}

}  // namespace

void parseMaterials(Scene& scene, const json& doc, const Document& d, const Reader& r) {
    const json& materials = r.topArray(doc, "materials");
    for (size_t i = 0; i < materials.size(); ++i)
        scene.materials.push_back(
            parseMaterial(materials[i], elementName("materials", i, materials[i]), d, r));
}

}  // namespace speculum::gltf
