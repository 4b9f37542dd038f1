// SPECULUM_reflections (materials) and SPECULUM_reflection_probe (nodes): parsing with
// validation, and writing back. The schema is in EXTENSIONS.md; keep the two in step.
#include "gltf_document.hpp"

#include <array>

namespace speculum::gltf {

namespace {

// `names` is the enum's names in value order (speculum/scene.hpp).
template <typename E, size_t N>
E parseEnum(const json& ext, const char* key, const std::string& where, E def,
            const std::array<const char*, N>& names, const Reader& r) {
    if (!ext.contains(key)) return def;
    std::string value = r.string(ext, key, where);
    std::string allowed;
    for (size_t i = 0; i < N; ++i) {
        if (value == names[i]) return E(i);
        allowed += std::string(allowed.empty() ? "" : ", ") + names[i];
    }
    r.fail(where + "." + key, "unknown value \"" + value + "\" (expected one of " + allowed + ")");
}

template <typename E, size_t N>
const char* enumName(E e, const std::array<const char*, N>& names) {
    return size_t(e) < N ? names[size_t(e)] : names[0];
}

float ranged(const json& ext, const char* key, const std::string& where, float def, float lo,
             float hi, const Reader& r) {
    double v = r.number(ext, key, where, def);
    if (v < lo || v > hi)
        r.fail(where + "." + key, std::to_string(v) + " is out of range [" + std::to_string(lo) +
                                      ", " + std::to_string(hi) + "]");
    return float(v);
}

// Unknown fields are not errors: a newer engine may have written them, and save keeps them.
void warnUnknown(const json& ext, const std::string& where,
                 std::initializer_list<const char*> known, const Reader& r) {
    for (auto it = ext.begin(); it != ext.end(); ++it) {
        bool ok = false;
        for (const char* k : known) ok = ok || it.key() == k;
        if (!ok && it.key() != "extras" && it.key() != "extensions")
            logWarning(r.file() + ": " + where + ": unknown field \"" + it.key() + "\" ignored");
    }
}

}  // namespace

MaterialReflections parseReflections(const json& ext, const std::string& where,
                                     const Reader& r) {
    MaterialReflections m;
    warnUnknown(ext, where,
                {"mode", "roughnessScale", "roughnessOverride", "maxScreenSpaceRoughness",
                 "traceCmos", "mirrorForSelfReflections"},
                r);
    m.mode = parseEnum(ext, "mode", where, m.mode, kReflectionModeNames, r);
    m.roughnessScale = ranged(ext, "roughnessScale", where, m.roughnessScale, 0.0f, 16.0f, r);
    if (ext.contains("roughnessOverride"))
        m.roughnessOverride = ranged(ext, "roughnessOverride", where, 0.0f, 0.0f, 1.0f, r);
    m.maxScreenSpaceRoughness =
        ranged(ext, "maxScreenSpaceRoughness", where, m.maxScreenSpaceRoughness, 0.0f, 1.0f, r);
    m.traceCmos = r.boolean(ext, "traceCmos", where, m.traceCmos);
    m.mirrorForSelfReflections =
        r.boolean(ext, "mirrorForSelfReflections", where, m.mirrorForSelfReflections);
    return m;
}

ReflectionProbe parseProbe(const json& ext, const std::string& where, const Reader& r) {
    ReflectionProbe p;
    warnUnknown(ext, where,
                {"kind", "shape", "extents", "blendDistance", "resolution", "update", "order"}, r);
    p.kind = parseEnum(ext, "kind", where, p.kind, kProbeKindNames, r);
    p.shape = parseEnum(ext, "shape", where, p.shape, kProbeShapeNames, r);
    const bool planar = p.kind == ProbeKind::Planar;
    // A planar probe's extents are the rectangle on its plane: [half width, half depth].
    auto e = planar ? r.floats(ext, "extents", where, 2, {p.extents.x, p.extents.y})
                    : r.floats(ext, "extents", where, 3, {p.extents.x, p.extents.y, p.extents.z});
    for (float v : e)
        if (!(v > 0.0f)) r.fail(where + ".extents", "every extent must be positive");
    p.extents = {e[0], e[1], planar ? 1.0f : e[2]};
    p.blendDistance = ranged(ext, "blendDistance", where, p.blendDistance, 0.0f, 1.0e6f, r);
    if (planar) {
        // The planar image's height; absent: half the view's (0). Below 16 px a mirror is a
        // blur; above 4096 it is over any view this engine renders.
        int64_t res = r.integer(ext, "resolution", where, 0);
        if (ext.contains("resolution") && (res < 16 || res > 4096))
            r.fail(where + ".resolution", std::to_string(res) + " is out of range [16, 4096] (image height in pixels)");
        p.resolution = uint32_t(res);
    } else {
        int64_t res = r.integer(ext, "resolution", where, p.resolution);
        // Faces are GGX-prefiltered down to 4x4 like the sky's cube, whose mips halve exactly.
        if (res < 8 || res > 4096 || (res & (res - 1)) != 0)
            r.fail(where + ".resolution", std::to_string(res) + " is not a power of two in [8, 4096]");
        p.resolution = uint32_t(res);
    }
    p.update = parseEnum(ext, "update", where, p.update, kProbeUpdateNames, r);
    int64_t order = r.integer(ext, "order", where, p.order);
    if (order < -1000000 || order > 1000000)
        r.fail(where + ".order", std::to_string(order) + " is out of range [-1e6, 1e6]");
    p.order = int(order);
    return p;
}

void writeReflections(json& ext, const MaterialReflections& m) {
    ext["mode"] = enumName(m.mode, kReflectionModeNames);
    ext["roughnessScale"] = m.roughnessScale;
    if (m.roughnessOverride) ext["roughnessOverride"] = *m.roughnessOverride;
    else ext.erase("roughnessOverride");
    ext["maxScreenSpaceRoughness"] = m.maxScreenSpaceRoughness;
    ext["traceCmos"] = m.traceCmos;
    ext["mirrorForSelfReflections"] = m.mirrorForSelfReflections;
}

void writeProbe(json& ext, const ReflectionProbe& p) {
    ext["kind"] = enumName(p.kind, kProbeKindNames);
    ext["shape"] = enumName(p.shape, kProbeShapeNames);
    ext["blendDistance"] = p.blendDistance;
    if (p.kind == ProbeKind::Planar) {
        ext["extents"] = {p.extents.x, p.extents.y};
        if (p.resolution > 0) ext["resolution"] = p.resolution;
        else ext.erase("resolution");
    } else {
        ext["extents"] = {p.extents.x, p.extents.y, p.extents.z};
        ext["resolution"] = p.resolution;
    }
    ext["update"] = enumName(p.update, kProbeUpdateNames);
    ext["order"] = p.order;
}

}  // namespace speculum::gltf
