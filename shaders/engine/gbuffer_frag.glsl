// The G-buffer fragment shader, compiled twice: gbuffer.frag samples the material's textures,
// gbuffer_untextured.frag (GBUFFER_UNTEXTURED) is for materials whose textures are all 1x1
// defaults. A uniform branch would not do: lavapipe runs both sides of every branch, so only a
// separate pipeline saves the four filtered lookups.
#include "engine/gbuffer_common.glsl"
#include "common/camera.glsl"

layout(set = 0, binding = 1) uniform sampler2D baseColorTex;          // sRGB view
layout(set = 0, binding = 2) uniform sampler2D metallicRoughnessTex;  // UNORM, g rough, b metal
layout(set = 0, binding = 3) uniform sampler2D normalTex;             // UNORM tangent space
layout(set = 0, binding = 4) uniform sampler2D emissiveTex;           // sRGB view

layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec4 inTangent;
layout(location = 2) in vec2 inUV;
layout(location = 3) in vec4 inClip;
layout(location = 4) in vec4 inPrevClip;

layout(location = 0) out vec4 outAlbedo;    // rgb albedo, a metallic
layout(location = 1) out vec4 outNormal;    // xyz world normal, w roughness
layout(location = 2) out vec4 outEmissive;  // rgb emissive (unlit: base colour), a flags
layout(location = 3) out vec2 outMotion;    // uv now - uv previous frame

#ifdef GBUFFER_UNTEXTURED
// The defaults' texels: white (the factors alone) and the exactly flat normal. (The 8-bit
// default texel (128, 128, 255) tilts normals by 0.3 degrees, which moves a mirror's
// reflection of something 10 m away by 5 cm: the untextured path must not carry it.)
#define SAMPLE_OR_WHITE(tex) vec4(1.0)
#define NORMAL_TEXEL vec3(0.5, 0.5, 1.0)
#else
#define SAMPLE_OR_WHITE(tex) texture(tex, inUV)
#define NORMAL_TEXEL texture(normalTex, inUV).xyz
#endif

vec3 shadingNormal(bool backFacing) {
    vec3 n = normalize(inNormal);
    vec3 t = inTangent.xyz - n * dot(n, inTangent.xyz);
    float tl = dot(t, t);
    if (backFacing) n = -n;
    if (tl > 1e-12) {
        t *= inversesqrt(tl);
        vec3 b = cross(n, t) * (inTangent.w < 0.0 ? -1.0 : 1.0);
        vec3 tn = NORMAL_TEXEL * 2.0 - 1.0;
        tn.xy *= draw.params.z;
        vec3 mapped = mat3(t, b, n) * tn;
        float ml = dot(mapped, mapped);
        if (ml > 1e-12) n = mapped * inversesqrt(ml);
    }
    return n;
}

void main() {
    uint drawFlags = uint(draw.params.w);
    uint materialFlags = uint(draw.emissive.w);
    bool frontFacing = gl_FrontFacing != ((drawFlags & kDrawInvertFacing) != 0u);
    bool backFacing = ((drawFlags & kDrawDoubleSided) != 0u) && !frontFacing;

    vec4 base = draw.baseColor * SAMPLE_OR_WHITE(baseColorTex);
    vec2 uvNow = ndcToUV(inClip.xy / inClip.w);
    vec2 uvPrev = ndcToUV(inPrevClip.xy / inPrevClip.w);
    outMotion = uvNow - uvPrev;

    if ((materialFlags & kFlagUnlit) != 0u) {
        // Unlit stores its linear base colour where lighting copies it verbatim.
        outAlbedo = vec4(0.0);
        outNormal = vec4(normalize(inNormal) * (backFacing ? -1.0 : 1.0), 1.0);
        outEmissive = vec4(base.rgb, float(materialFlags));
        return;
    }
    vec4 mr = SAMPLE_OR_WHITE(metallicRoughnessTex);
    float metallic = clamp(draw.params.x * mr.b, 0.0, 1.0);
    float roughness = clamp(draw.params.y * mr.g, 0.0, 1.0);
    outAlbedo = vec4(base.rgb, metallic);
    outNormal = vec4(shadingNormal(backFacing), roughness);
    outEmissive =
        vec4(draw.emissive.rgb * SAMPLE_OR_WHITE(emissiveTex).rgb, float(materialFlags));
}
