// Meshes from accessors: reading any component type, sparse substitution, index checks, and
// normals/tangents where the file has none. Byte ranges were validated in validate.cpp.
#include "gltf_document.hpp"

#include "speculum/limits.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace speculum::gltf {

namespace {

template <typename T>
T load(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));  // accessor data need not be aligned for the host
    return v;
}

float decodeComponent(const uint8_t* p, uint32_t type, bool normalized) {
    switch (type) {
        case 5126: return load<float>(p);
        case 5120: {
            float v = float(load<int8_t>(p));
            return normalized ? std::max(v / 127.0f, -1.0f) : v;
        }
        case 5121: return normalized ? load<uint8_t>(p) / 255.0f : float(load<uint8_t>(p));
        case 5122: {
            float v = float(load<int16_t>(p));
            return normalized ? std::max(v / 32767.0f, -1.0f) : v;
        }
        case 5123: return normalized ? load<uint16_t>(p) / 65535.0f : float(load<uint16_t>(p));
        case 5125: return float(load<uint32_t>(p));
        default: return 0.0f;
    }
}

uint32_t decodeIndex(const uint8_t* p, uint32_t type) {
    switch (type) {
        case 5121: return load<uint8_t>(p);
        case 5123: return load<uint16_t>(p);
        default: return load<uint32_t>(p);
    }
}

uint32_t componentBytes(uint32_t type) {
    return type == 5120 || type == 5121 ? 1 : type == 5122 || type == 5123 ? 2 : 4;
}

const uint8_t* viewData(const Scene& s, const Document& d, int view, uint64_t offset) {
    const BufferViewInfo& v = d.bufferViews[view];
    return s.buffers[v.buffer].data() + v.byteOffset + offset;
}

// Accessor contents as floats, count * components, with sparse values applied.
std::vector<float> readFloats(const Scene& s, const Document& d, int accessor, const Reader& r) {
    const AccessorInfo& a = d.accessors[accessor];
    const uint32_t csize = componentBytes(a.componentType);
    const uint64_t elem = uint64_t(csize) * a.components;
    std::vector<float> out(size_t(a.count) * a.components, 0.0f);
    if (a.bufferView >= 0) {
        uint64_t stride = d.bufferViews[a.bufferView].byteStride;
        if (stride == 0) stride = elem;
        const uint8_t* base = viewData(s, d, a.bufferView, a.byteOffset);
        for (uint32_t i = 0; i < a.count; ++i)
            for (int c = 0; c < a.components; ++c)
                out[size_t(i) * a.components + c] =
                    decodeComponent(base + i * stride + c * csize, a.componentType, a.normalized);
    }
    if (a.sparse) {
        const SparseInfo& sp = *a.sparse;
        const uint8_t* idx = viewData(s, d, sp.indicesView, sp.indicesOffset);
        const uint8_t* val = viewData(s, d, sp.valuesView, sp.valuesOffset);
        const uint32_t isize = componentBytes(sp.indicesComponentType);
        for (uint32_t k = 0; k < sp.count; ++k) {
            uint32_t target = decodeIndex(idx + k * isize, sp.indicesComponentType);
            if (target >= a.count)
                r.fail(a.where + ".sparse", "index " + std::to_string(target) +
                                                " is beyond the accessor count");
            for (int c = 0; c < a.components; ++c)
                out[size_t(target) * a.components + c] = decodeComponent(
                    val + k * elem + c * csize, a.componentType, a.normalized);
        }
    }
    for (size_t i = 0; i < out.size(); ++i)
        if (!std::isfinite(out[i]))
            r.fail(a.where, "element " + std::to_string(i / a.components) +
                                " is not finite (NaN or infinity)");
    return out;
}

std::vector<uint32_t> readIndices(const Scene& s, const Document& d, int accessor,
                                  const Reader& r) {
    const AccessorInfo& a = d.accessors[accessor];
    if (a.sparse) {  // rare enough for indices that the float path's precision is fine
        std::vector<float> f = readFloats(s, d, accessor, r);
        return {f.begin(), f.end()};
    }
    std::vector<uint32_t> out(a.count, 0);
    if (a.bufferView < 0) return out;
    const uint32_t csize = componentBytes(a.componentType);
    uint64_t stride = d.bufferViews[a.bufferView].byteStride;
    if (stride == 0) stride = csize;
    const uint8_t* base = viewData(s, d, a.bufferView, a.byteOffset);
    for (uint32_t i = 0; i < a.count; ++i) out[i] = decodeIndex(base + i * stride, a.componentType);
    return out;
}

// Strips and fans become lists so the renderer only ever sees one topology.
std::vector<uint32_t> toTriangleList(const std::vector<uint32_t>& in, int mode,
                                     const std::string& where, const Reader& r) {
    if (mode == 4) {
        if (in.size() % 3 != 0)
            r.fail(where, std::to_string(in.size()) + " indices is not a multiple of 3");
        return in;
    }
    std::vector<uint32_t> out;
    for (size_t i = 0; i + 2 < in.size(); ++i) {
        if (mode == 5) {
            bool even = i % 2 == 0;
            out.insert(out.end(), {in[even ? i : i + 1], in[even ? i + 1 : i], in[i + 2]});
        } else {
            out.insert(out.end(), {in[0], in[i + 1], in[i + 2]});
        }
    }
    return out;
}

void fillAttributes(Primitive& p, const Scene& s, const Document& d, const PrimitiveInfo& info,
                    const Reader& r) {
    std::vector<float> pos = readFloats(s, d, info.position, r);
    const size_t n = pos.size() / 3;
    p.vertices.resize(n);
    for (size_t i = 0; i < n; ++i) {
        p.vertices[i].position = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
        p.vertices[i].normal = glm::vec3(0.0f);
        p.vertices[i].tangent = glm::vec4(0.0f);
        p.vertices[i].uv = glm::vec2(0.0f);
    }
    if (info.normal >= 0) {
        std::vector<float> v = readFloats(s, d, info.normal, r);
        for (size_t i = 0; i < n; ++i) {
            glm::vec3 nrm(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
            float len = glm::length(nrm);
            p.vertices[i].normal = len > 1e-20f ? nrm / len : glm::vec3(0, 0, 1);
        }
    }
    if (info.tangent >= 0) {
        std::vector<float> v = readFloats(s, d, info.tangent, r);
        for (size_t i = 0; i < n; ++i)
            p.vertices[i].tangent = {v[4 * i], v[4 * i + 1], v[4 * i + 2],
                                     v[4 * i + 3] < 0.0f ? -1.0f : 1.0f};
    }
    if (info.texcoord0 >= 0) {
        std::vector<float> v = readFloats(s, d, info.texcoord0, r);
        for (size_t i = 0; i < n; ++i) p.vertices[i].uv = {v[2 * i], v[2 * i + 1]};
    }
}

bool buildPrimitive(Primitive& p, const Scene& s, const Document& d, const PrimitiveInfo& info,
                    const Reader& r) {
    if (info.position < 0) {
        logWarning(r.file() + ": " + info.where + ": no POSITION attribute; primitive skipped");
        return false;
    }
    if (info.mode < 4) {
        logWarning(r.file() + ": " + info.where + ": points/lines (mode " +
                   std::to_string(info.mode) + ") are not supported; primitive skipped");
        return false;
    }
    fillAttributes(p, s, d, info, r);
    const uint32_t n = uint32_t(p.vertices.size());
    std::vector<uint32_t> indices;
    if (info.indices >= 0) {
        indices = readIndices(s, d, info.indices, r);
        for (size_t i = 0; i < indices.size(); ++i)
            if (indices[i] >= n)
                r.fail(info.where + ".indices",
                       "index value " + std::to_string(indices[i]) + " at position " +
                           std::to_string(i) + " is beyond the vertex count " + std::to_string(n));
    } else {
        indices.resize(n);
        for (uint32_t i = 0; i < n; ++i) indices[i] = i;
    }
    p.indices = toTriangleList(indices, info.mode, info.where, r);
    p.material = info.material;
    if (info.normal < 0) generateNormals(p);
    if (info.tangent < 0) generateTangents(p);
    p.boundsMin = glm::vec3(std::numeric_limits<float>::max());
    p.boundsMax = glm::vec3(-std::numeric_limits<float>::max());
    for (const Vertex& v : p.vertices) {
        p.boundsMin = glm::min(p.boundsMin, v.position);
        p.boundsMax = glm::max(p.boundsMax, v.position);
    }
    return true;
}

}  // namespace

void generateNormals(Primitive& p) {
    // Unnormalised cross products weight each face by its area, so slivers barely count.
    for (Vertex& v : p.vertices) v.normal = glm::vec3(0.0f);
    for (size_t t = 0; t + 2 < p.indices.size(); t += 3) {
        Vertex& a = p.vertices[p.indices[t]];
        Vertex& b = p.vertices[p.indices[t + 1]];
        Vertex& c = p.vertices[p.indices[t + 2]];
        glm::vec3 n = glm::cross(b.position - a.position, c.position - a.position);
        a.normal += n;
        b.normal += n;
        c.normal += n;
    }
    for (Vertex& v : p.vertices) {
        float len = glm::length(v.normal);
        v.normal = len > 1e-30f && std::isfinite(len) ? v.normal / len : glm::vec3(0, 0, 1);
    }
}

// The expanded size of every primitive, from the accessor counts alone, before any vertex is
// built: one accessor reused by many primitives is copied into each (limits.hpp).
static void checkGeometrySize(const Document& d, const Reader& r) {
    uint64_t vertices = 0, indices = 0;
    for (const MeshInfo& info : d.meshes)
        for (const PrimitiveInfo& pi : info.primitives) {
            if (pi.position < 0 || pi.mode < 4) continue;
            uint64_t n = d.accessors[size_t(pi.position)].count;
            uint64_t k = pi.indices >= 0 ? d.accessors[size_t(pi.indices)].count : n;
            vertices += n;
            indices += pi.mode == 4 ? k : 3 * k;  // strips and fans become up to 3 per index
        }
    uint64_t bytes = vertices * sizeof(Vertex) + indices * sizeof(uint32_t);
    if (bytes > limits::kMaxSceneGeometryBytes)
        r.fail("meshes", "the primitives expand to " + std::to_string(vertices) + " vertices and " +
                             std::to_string(indices) + " indices (" + limits::bytesText(bytes) +
                             "), more than the " + limits::bytesText(limits::kMaxSceneGeometryBytes) +
                             " limit for a scene");
}

void buildMeshes(Scene& scene, const Document& d, const Reader& r) {
    checkGeometrySize(d, r);
    for (const MeshInfo& info : d.meshes) {
        Mesh mesh;
        mesh.name = info.name;
        for (const PrimitiveInfo& pi : info.primitives) {
            Primitive p;
            if (buildPrimitive(p, scene, d, pi, r)) mesh.primitives.push_back(std::move(p));
        }
        scene.meshes.push_back(std::move(mesh));
    }
}

}  // namespace speculum::gltf
