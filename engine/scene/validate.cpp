// Structural validation of a glTF document: types, required fields, index ranges and byte
// ranges, all before a single buffer byte is read. tinygltf is lenient about some of these (it
// skips what it cannot parse), so we never rely on it for validity.
#include "gltf_document.hpp"

#include <array>

namespace speculum::gltf {

namespace {

uint32_t componentSize(uint32_t componentType) {
    switch (componentType) {
        case 5120: case 5121: return 1;
        case 5122: case 5123: return 2;
        case 5125: case 5126: return 4;
        default: return 0;
    }
}

int componentCount(const std::string& type) {
    static const std::array<std::pair<const char*, int>, 7> kTypes = {{
        {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9},
        {"MAT4", 16}}};
    for (const auto& [name, n] : kTypes)
        if (type == name) return n;
    return 0;
}

void checkAsset(const json& doc, const Reader& r) {
    const json* asset = r.object(doc, "asset", "");
    if (!asset) r.fail("", "not a glTF document: no \"asset\" object");
    std::string version = r.string(*asset, "version", "asset");
    if (version.empty()) r.fail("asset.version", "missing (required)");
    if (version[0] != '2') r.fail("asset.version", "unsupported glTF version " + version);
    // A required extension we do not implement means the file cannot be shown correctly.
    static const char* const kSupported[] = {"KHR_lights_punctual", "KHR_materials_unlit",
                                             "KHR_materials_emissive_strength", kReflectionsExt,
                                             kProbeExt};
    if (const json* required = r.array(doc, "extensionsRequired", "")) {
        for (const json& e : *required) {
            if (!e.is_string()) r.fail("extensionsRequired", "expected strings");
            bool ok = false;
            for (const char* s : kSupported) ok = ok || e.get<std::string>() == s;
            if (!ok)
                r.fail("extensionsRequired",
                       "requires \"" + e.get<std::string>() + "\", which is not supported");
        }
    }
}

void parseBuffers(const json& doc, Document& d, const Reader& r) {
    r.forEach(doc, "buffers", [&](const json& b, const std::string& where) {
        BufferInfo info;
        int64_t length = r.integer(b, "byteLength", where, -1);
        if (length < 0) r.fail(where + ".byteLength", "missing or negative");
        if (uint64_t(length) > kMaxBufferBytes)
            r.fail(where + ".byteLength", std::to_string(length) + " is absurdly large");
        info.byteLength = uint64_t(length);
        info.uri = r.string(b, "uri", where);
        d.buffers.push_back(info);
    });
    r.forEach(doc, "bufferViews", [&](const json& v, const std::string& where) {
        BufferViewInfo info;
        info.buffer = r.index(v, "buffer", where, d.buffers.size(), "buffers", true);
        int64_t offset = r.integer(v, "byteOffset", where, 0);
        int64_t length = r.integer(v, "byteLength", where, -1);
        int64_t stride = r.integer(v, "byteStride", where, 0);
        if (offset < 0) r.fail(where + ".byteOffset", "negative");
        if (length < 0) r.fail(where + ".byteLength", "missing or negative");
        if (stride != 0 && (stride < 4 || stride > 252 || stride % 4 != 0))
            r.fail(where + ".byteStride", std::to_string(stride) +
                                              " is not a multiple of 4 in [4, 252]");
        uint64_t end = uint64_t(offset) + uint64_t(length);
        if (end > d.buffers[info.buffer].byteLength)
            r.fail(where, "byte range [" + std::to_string(offset) + ", " + std::to_string(end) +
                              ") is beyond the end of buffer " + std::to_string(info.buffer) +
                              " (" + std::to_string(d.buffers[info.buffer].byteLength) +
                              " bytes)");
        info.byteOffset = uint64_t(offset);
        info.byteLength = uint64_t(length);
        info.byteStride = uint32_t(stride);
        d.bufferViews.push_back(info);
    });
}

// Checks that `count` elements of `elemSize` bytes at `offset` with `stride` fit in a view.
void checkRange(const Document& d, int view, uint64_t offset, uint64_t stride, uint64_t count,
                uint64_t elemSize, const std::string& where, const Reader& r) {
    uint64_t need = offset + stride * (count - 1) + elemSize;
    uint64_t have = d.bufferViews[view].byteLength;
    if (need > have)
        r.fail(where, "needs " + std::to_string(need) + " bytes of buffer view " +
                          std::to_string(view) + ", which has only " + std::to_string(have));
}

SparseInfo parseSparse(const json& s, const AccessorInfo& a, uint64_t elemSize,
                       const Document& d, const Reader& r) {
    std::string where = a.where + ".sparse";
    SparseInfo info;
    int64_t count = r.integer(s, "count", where, -1);
    if (count < 1 || uint64_t(count) > a.count)
        r.fail(where + ".count", "must be in [1, accessor count]");
    info.count = uint32_t(count);
    const json* idx = r.object(s, "indices", where);
    const json* val = r.object(s, "values", where);
    if (!idx || !val) r.fail(where, "needs \"indices\" and \"values\"");
    info.indicesView = r.index(*idx, "bufferView", where + ".indices", d.bufferViews.size(),
                               "bufferViews", true);
    info.indicesOffset = uint64_t(std::max<int64_t>(0, r.integer(*idx, "byteOffset", where, 0)));
    info.indicesComponentType = uint32_t(r.integer(*idx, "componentType", where, 0));
    uint32_t isize = componentSize(info.indicesComponentType);
    if (isize == 0 || info.indicesComponentType == 5126 || info.indicesComponentType < 5121 ||
        info.indicesComponentType == 5122)
        r.fail(where + ".indices.componentType", "must be an unsigned integer type");
    checkRange(d, info.indicesView, info.indicesOffset, isize, info.count, isize,
               where + ".indices", r);
    info.valuesView = r.index(*val, "bufferView", where + ".values", d.bufferViews.size(),
                              "bufferViews", true);
    info.valuesOffset = uint64_t(std::max<int64_t>(0, r.integer(*val, "byteOffset", where, 0)));
    checkRange(d, info.valuesView, info.valuesOffset, elemSize, info.count, elemSize,
               where + ".values", r);
    return info;
}

void parseAccessors(const json& doc, Document& d, const Reader& r) {
    const json& accessors = r.topArray(doc, "accessors");
    for (size_t i = 0; i < accessors.size(); ++i) {
        const json& a = accessors[i];
        AccessorInfo info;
        info.where = elementName("accessors", i, a);
        const std::string& where = info.where;
        info.componentType = uint32_t(r.integer(a, "componentType", where, 0));
        uint32_t csize = componentSize(info.componentType);
        if (csize == 0) r.fail(where + ".componentType", "missing or not a glTF component type");
        info.components = componentCount(r.string(a, "type", where));
        if (info.components == 0) r.fail(where + ".type", "missing or not a glTF accessor type");
        info.normalized = r.boolean(a, "normalized", where, false);
        int64_t count = r.integer(a, "count", where, -1);
        if (count < 1) r.fail(where + ".count", "missing or less than 1");
        if (uint64_t(count) > kMaxAccessorCount)
            r.fail(where + ".count", std::to_string(count) + " is absurdly large (limit " +
                                         std::to_string(kMaxAccessorCount) + ")");
        info.count = uint32_t(count);
        info.bufferView = r.index(a, "bufferView", where, d.bufferViews.size(), "bufferViews");
        int64_t offset = r.integer(a, "byteOffset", where, 0);
        if (offset < 0) r.fail(where + ".byteOffset", "negative");
        if (offset % csize != 0)
            r.fail(where + ".byteOffset", "not a multiple of the component size");
        info.byteOffset = uint64_t(offset);
        uint64_t elemSize = uint64_t(csize) * info.components;
        if (info.bufferView >= 0) {
            uint64_t stride = d.bufferViews[info.bufferView].byteStride;
            if (stride == 0) stride = elemSize;
            if (stride < elemSize)
                r.fail(where, "byteStride of its buffer view is smaller than one element");
            checkRange(d, info.bufferView, info.byteOffset, stride, info.count, elemSize, where,
                       r);
        }
        if (const json* s = r.object(a, "sparse", where))
            info.sparse = parseSparse(*s, info, elemSize, d, r);
        d.accessors.push_back(std::move(info));
    }
}

// Accessor type/format rules for the attributes we read, so reading never misinterprets bytes.
void checkAttribute(const Document& d, int accessor, const char* name, int components,
                    bool allowNormalizedInts, const std::string& where, const Reader& r) {
    if (accessor < 0) return;
    const AccessorInfo& a = d.accessors[accessor];
    bool isFloat = a.componentType == 5126;
    bool okInt = allowNormalizedInts && a.normalized &&
                 (a.componentType == 5121 || a.componentType == 5123);
    if (a.components != components || !(isFloat || okInt))
        r.fail(where + ".attributes." + name, "accessor " + std::to_string(accessor) +
                                                  " has the wrong type or component type");
}

PrimitiveInfo parsePrimitive(const json& p, const std::string& where, const Document& d,
                             size_t materialCount, const Reader& r) {
    PrimitiveInfo info;
    info.where = where;
    const json* attrs = r.object(p, "attributes", where);
    if (!attrs) r.fail(where + ".attributes", "missing (required)");
    size_t n = d.accessors.size();
    std::string aw = where + ".attributes";
    for (auto it = attrs->begin(); it != attrs->end(); ++it)
        r.index(*attrs, it.key().c_str(), aw, n, "accessors", true);
    info.position = r.index(*attrs, "POSITION", aw, n, "accessors");
    info.normal = r.index(*attrs, "NORMAL", aw, n, "accessors");
    info.tangent = r.index(*attrs, "TANGENT", aw, n, "accessors");
    info.texcoord0 = r.index(*attrs, "TEXCOORD_0", aw, n, "accessors");
    info.indices = r.index(p, "indices", where, n, "accessors");
    info.material = r.index(p, "material", where, materialCount, "materials");
    int64_t mode = r.integer(p, "mode", where, 4);
    if (mode < 0 || mode > 6) r.fail(where + ".mode", "not a glTF primitive mode (0..6)");
    info.mode = int(mode);
    checkAttribute(d, info.position, "POSITION", 3, false, where, r);
    checkAttribute(d, info.normal, "NORMAL", 3, false, where, r);
    checkAttribute(d, info.tangent, "TANGENT", 4, false, where, r);
    checkAttribute(d, info.texcoord0, "TEXCOORD_0", 2, true, where, r);
    if (info.position >= 0) {
        uint32_t count = d.accessors[info.position].count;
        for (int other : {info.normal, info.tangent, info.texcoord0})
            if (other >= 0 && d.accessors[other].count != count)
                r.fail(where + ".attributes", "attribute accessors differ in count");
    }
    if (info.indices >= 0) {
        const AccessorInfo& a = d.accessors[info.indices];
        if (a.components != 1 ||
            (a.componentType != 5121 && a.componentType != 5123 && a.componentType != 5125))
            r.fail(where + ".indices", "accessor must be SCALAR unsigned byte/short/int");
    }
    return info;
}

void parseMeshes(const json& doc, Document& d, const Reader& r) {
    r.forEach(doc, "meshes", [&](const json& m, const std::string& where) {
        MeshInfo info;
        info.name = r.string(m, "name", where);
        const json* prims = r.array(m, "primitives", where);
        if (!prims || prims->empty()) r.fail(where + ".primitives", "missing or empty");
        for (size_t p = 0; p < prims->size(); ++p) {
            std::string pw = where + ".primitives[" + std::to_string(p) + "]";
            if (!(*prims)[p].is_object()) r.fail(pw, "expected an object");
            info.primitives.push_back(parsePrimitive((*prims)[p], pw, d, d.materialCount, r));
        }
        d.meshes.push_back(std::move(info));
    });
}

void parseTexturesAndImages(const json& doc, Document& d, const Reader& r) {
    const json& images = r.topArray(doc, "images");
    for (size_t i = 0; i < images.size(); ++i) {
        const json& im = images[i];
        std::string where = elementName("images", i, im);
        ImageInfo info;
        info.uri = r.string(im, "uri", where);
        info.bufferView = r.index(im, "bufferView", where, d.bufferViews.size(), "bufferViews");
        if (info.uri.empty() == (info.bufferView < 0))
            r.fail(where, "needs exactly one of \"uri\" and \"bufferView\"");
        r.string(im, "mimeType", where);
        info.name = r.string(im, "name", where);
        if (info.name.empty()) info.name = info.uri;
        if (info.name.empty() || isDataUri(info.name)) info.name = "image " + std::to_string(i);
        d.images.push_back(std::move(info));
    }
    const json& textures = r.topArray(doc, "textures");
    for (size_t i = 0; i < textures.size(); ++i) {
        std::string where = elementName("textures", i, textures[i]);
        r.index(textures[i], "sampler", where, r.topArray(doc, "samplers").size(), "samplers");
        d.textureSources.push_back(
            r.index(textures[i], "source", where, d.images.size(), "images"));
    }
}

void parseLightDefs(const json& doc, Document& d, const Reader& r) {
    const json* exts = r.object(doc, "extensions", "");
    if (!exts) return;
    const json* punctual = r.object(*exts, "KHR_lights_punctual", "extensions");
    if (!punctual) return;
    const char* base = "extensions.KHR_lights_punctual";
    const json* lights = r.array(*punctual, "lights", base);
    if (!lights) return;
    for (size_t i = 0; i < lights->size(); ++i) {
        const json& l = (*lights)[i];
        std::string where = std::string(base) + "." + elementName("lights", i, l);
        if (!l.is_object()) r.fail(where, "expected an object");
        Light light;
        light.name = r.string(l, "name", where);
        std::string type = r.string(l, "type", where);
        if (type == "directional") light.type = LightType::Directional;
        else if (type == "point") light.type = LightType::Point;
        else if (type == "spot") light.type = LightType::Spot;
        else r.fail(where + ".type", "\"" + type + "\" is not directional, point or spot");
        auto c = r.floats(l, "color", where, 3, {1, 1, 1});
        light.color = {c[0], c[1], c[2]};
        light.intensity = float(r.number(l, "intensity", where, 1.0));
        light.range = float(r.number(l, "range", where, 0.0));
        if (light.intensity < 0 || light.range < 0)
            r.fail(where, "intensity and range must not be negative");
        if (light.type == LightType::Spot) {
            const json* spot = r.object(l, "spot", where);
            if (spot) {
                light.innerConeAngle = float(r.number(*spot, "innerConeAngle", where, 0.0));
                light.outerConeAngle =
                    float(r.number(*spot, "outerConeAngle", where, 0.7853981634));
            }
            if (light.innerConeAngle < 0 || light.innerConeAngle >= light.outerConeAngle ||
                light.outerConeAngle > 1.5707964f)
                r.fail(where + ".spot", "need 0 <= innerConeAngle < outerConeAngle <= pi/2");
        }
        d.lights.push_back(light);
    }
}

void parseCameraDefs(const json& doc, Document& d, const Reader& r) {
    r.forEach(doc, "cameras", [&](const json& c, const std::string& where) {
        Camera cam;
        cam.name = r.string(c, "name", where);
        std::string type = r.string(c, "type", where);
        cam.perspective = type == "perspective";
        if (!cam.perspective && type != "orthographic")
            r.fail(where + ".type", "must be \"perspective\" or \"orthographic\"");
        const json* p = r.object(c, type.c_str(), where);
        if (!p) r.fail(where, "missing the \"" + type + "\" object");
        std::string pw = where + "." + type;
        if (cam.perspective) {
            cam.yfov = float(r.number(*p, "yfov", pw, -1.0));
            cam.aspectRatio = float(r.number(*p, "aspectRatio", pw, 0.0));
            cam.znear = float(r.number(*p, "znear", pw, -1.0));
            cam.zfar = float(r.number(*p, "zfar", pw, 0.0));
            if (cam.yfov <= 0 || cam.yfov >= 3.1415926f)
                r.fail(pw + ".yfov", "missing or not in (0, pi)");
        } else {
            cam.xmag = float(r.number(*p, "xmag", pw, 0.0));
            cam.ymag = float(r.number(*p, "ymag", pw, 0.0));
            cam.znear = float(r.number(*p, "znear", pw, -1.0));
            cam.zfar = float(r.number(*p, "zfar", pw, -1.0));
            if (cam.xmag == 0 || cam.ymag == 0) r.fail(pw, "xmag and ymag must be non-zero");
        }
        if (cam.znear < 0 || (cam.perspective && cam.znear == 0))
            r.fail(pw + ".znear", "missing or not positive");
        if (cam.aspectRatio < 0) r.fail(pw + ".aspectRatio", "negative");
        if (cam.zfar != 0 && cam.zfar <= cam.znear) r.fail(pw + ".zfar", "not beyond znear");
        d.cameras.push_back(cam);
    });
}

void parseSceneChoice(const json& doc, Document& d, const Reader& r) {
    size_t nodeCount = r.topArray(doc, "nodes").size();
    if (nodeCount == 0) r.fail("", "the scene has no nodes");
    const json& scenes = r.topArray(doc, "scenes");
    for (size_t i = 0; i < scenes.size(); ++i) {
        std::string where = elementName("scenes", i, scenes[i]);
        const json* nodes = r.array(scenes[i], "nodes", where);
        if (!nodes) continue;
        for (size_t k = 0; k < nodes->size(); ++k)
            if (!(*nodes)[k].is_number_integer() || (*nodes)[k].get<int64_t>() < 0 ||
                uint64_t((*nodes)[k].get<int64_t>()) >= nodeCount)
                r.fail(where + ".nodes[" + std::to_string(k) + "]",
                       "not a node index in range (the file has " + std::to_string(nodeCount) +
                           " nodes)");
    }
    d.sceneIndex = r.index(doc, "scene", "", scenes.size(), "scenes");
    if (d.sceneIndex < 0 && !scenes.empty()) d.sceneIndex = 0;
    if (d.sceneIndex >= 0) {
        const json* nodes = r.array(scenes[d.sceneIndex], "nodes", "");
        if (!nodes || nodes->empty())
            r.fail(elementName("scenes", d.sceneIndex, scenes[d.sceneIndex]),
                   "the scene has no nodes");
    }
}

}  // namespace

Document parseDocument(const json& doc, const Reader& r) {
    Document d;
    checkAsset(doc, r);
    d.materialCount = r.topArray(doc, "materials").size();
    parseBuffers(doc, d, r);
    parseAccessors(doc, d, r);
    parseMeshes(doc, d, r);
    parseTexturesAndImages(doc, d, r);
    parseLightDefs(doc, d, r);
    parseCameraDefs(doc, d, r);
    parseSceneChoice(doc, d, r);
    return d;
}

}  // namespace speculum::gltf
