// Per-material reflection settings (SPECULUM_reflections), looked up by the material index the
// G-buffer stores above its flags. Include after common.glsl; the including shader binds the
// table at binding 4.
#ifndef SPECULUM_REFLECTIONS_MATERIAL_GLSL
#define SPECULUM_REFLECTIONS_MATERIAL_GLSL

layout(set = 0, binding = 4, std430) readonly buffer MaterialTable {
    vec4 materials[];  // mode | 4 traceCmos, roughness scale, roughness override (< 0 none), max SS roughness
};

struct PixelMaterial {
    bool reflective;      // flagged, lit, and mode != off
    bool screenSpace;     // mode screen space + fallbacks
    bool traceCmos;       // CMOs in its chain (SPECULUM_reflections traceCmos)
    float roughness;      // the reflection's perceptual roughness
    float maxScreenSpace; // min(material, global) screen-space roughness limit
};

PixelMaterial pixelMaterial(float flagsValue, float gbufferRoughness) {
    uint flags = uint(flagsValue);
    PixelMaterial m;
    uint index = min(flags >> kMaterialIndexShift, rf.materialCount - 1u);
    vec4 p = materials[index];
    uint mode = uint(p.x) & 3u;
    m.reflective = (flags & kFlagReflective) != 0u && (flags & kFlagUnlit) == 0u && mode != kModeOff;
    m.screenSpace = mode == kModeScreenSpace;
    m.traceCmos = (uint(p.x) & 4u) != 0u;
    m.roughness = clamp(p.z >= 0.0 ? p.z : gbufferRoughness * p.y, 0.0, 1.0);
    m.maxScreenSpace = min(p.w, rf.maxRoughness);
    return m;
}

// The G-buffer block every per-pixel pass starts with: the pixel's reversed-Z depth (level 0 of
// the Hi-Z pyramid `hizTex`, whose g is the pixel's own depth), its normal and roughness, and
// its material.
PixelMaterial readSurface(sampler2D hizTex, sampler2D normals, sampler2D emissive, ivec2 pixel, out float depth,
                          out vec4 normalRough) {
    depth = texelFetch(hizTex, pixel, 0).g;
    normalRough = texelFetch(normals, pixel, 0);
    return pixelMaterial(texelFetch(emissive, pixel, 0).a, normalRough.w);
}

#endif
