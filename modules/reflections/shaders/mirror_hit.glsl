// A screen-space hit on a mirror (issue 24): the colour pyramid holds that mirror as the camera saw
// it, its reflection toward the camera, but the ray needs its reflection toward the reflecting
// point. reflections.resolve shades such a hit for the ray (mirrorHit), and its reflection along
// the ray reflected again comes from reflections.cmo_trace where the CMOs find it, else from the
// local probes and the sky. The tests here are shared by reflections.trace (which lists the CMO
// trace's tiles), reflections.cmo_trace and reflections.resolve, so that they cannot disagree.
// Include after common.glsl and material.glsl, where the includer declares hiz (level 0 .g: depth),
// normalTex and emissiveTex.
#ifndef SPECULUM_REFLECTIONS_MIRROR_HIT_GLSL
#define SPECULUM_REFLECTIONS_MIRROR_HIT_GLSL

// The radius of the circle inscribed in the isosceles triangle of this base and height.
float incircleRadius(float base, float height) {
    if (height <= 0.0 || base <= 0.0) return 0.0;
    return base * (sqrt(base * base + 4.0 * height * height) - base) / (4.0 * height);
}

// How much of the cone's colour a mirror hit replaces: all where the cone is narrow at the hit
// (its largest incircle at most a pixel), fading out by 2 px: a wider cone reads the pyramid's
// mips around the hit, which a single re-reflection does not stand for. px: the pixel's centre.
float mirrorHitShare(vec2 px, vec2 hit, float roughness) {
    float toHit = length(hit - px);
    return clamp(2.0 - incircleRadius(2.0 * coneTan(roughness) * toHit, toHit), 0.0, 1.0);
}

// The normal at the hit's sub-pixel position: the four G-buffer normals around it, bilinearly,
// those of the hit's surface only (within 2% of its distance, within 45 degrees of the nearest
// pixel's normal `nq`). On a curved mirror the nearest pixel's normal is up to half a pixel
// off, and a reflection reflected again turns that into an edge a pixel or more off
// (issue 24, sub-pixel registration).
vec3 hitNormal(vec3 hit, vec3 nq) {
    vec2 f = hit.xy - 0.5;
    ivec2 base = ivec2(floor(f));
    vec2 w = f - vec2(base);
    float z = linearDepth(hit.z);
    vec3 sum = vec3(0.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, i >> 1);
        ivec2 t = clamp(base + o, ivec2(0), ivec2(rf.size.xy) - 1);
        vec3 nt = normalize(texelFetch(normalTex, t, 0).xyz);
        float wt = (o.x != 0 ? w.x : 1.0 - w.x) * (o.y != 0 ? w.y : 1.0 - w.y);
        bool same = abs(linearDepth(texelFetch(hiz, t, 0).g) - z) <= 0.02 * z && dot(nt, nq) > 0.7;
        sum += same ? wt * nt : vec3(0.0);
    }
    return dot(sum, sum) > 1e-8 ? normalize(sum) : nq;
}

struct MirrorHit {
    ivec2 q;           // the hit's pixel
    PixelMaterial m;   // its material
    vec4 normalRough;  // its G-buffer normal and roughness
    vec3 position;     // the hit's world position
    vec3 d;            // the ray's direction toward it
    vec3 n;            // the normal at the hit's sub-pixel position
};

// The surface under screen-space hit `hit` (xy pixel, z depth) of the ray from p, when it is a
// mirror that reflections.resolve shades for the ray: reflective, smoother than
// rf.hitReflectMaxRoughness, seen from its front, and a local probe in the chain. Without a local
// probe the second bounce would be the sky alone: right outdoors, but indoors the pyramid's view
// of the room is closer (the gallery with probes off: gross errors on 40.8% of its reflective
// pixels against 40.0%), and the chain cannot tell the two apart, so there the pyramid's value
// stays. `withNormal` false skips the sub-pixel normal and the facing test (a superset, for the
// tile lists).
bool findMirrorHit(vec3 hit, vec3 p, bool withNormal, out MirrorHit h) {
    h.q = clamp(ivec2(hit.xy), ivec2(0), ivec2(rf.size.xy) - 1);
    h.position = vec3(0.0);
    h.d = vec3(0.0);
    h.n = vec3(0.0);
    if (rf.probeCount == 0u) return false;
    float qDepth;
    h.m = readSurface(hiz, normalTex, emissiveTex, h.q, qDepth, h.normalRough);
    if (!(qDepth > 0.0 && h.m.reflective && h.m.roughness < rf.hitReflectMaxRoughness)) return false;
    if (!withNormal) return true;
    h.position = worldAt(hit.xy, hit.z);
    h.d = normalize(h.position - p);
    h.n = hitNormal(hit, normalize(h.normalRough.xyz));
    return dot(h.n, -h.d) > 0.0;
}

// Whether reflections.cmo_trace traces the second bounce of this pixel's screen-space hit: screen
// space covers the pixel whole (where it does not, the CMOs trace the pixel's own ray instead),
// the cone is narrow enough at the hit for resolve's mirrorHit, and the hit is such a mirror whose
// material takes CMOs. px: the pixel's centre.
bool secondBounceInCmos(bool covered, vec2 px, vec4 hit, vec3 p, float roughness, bool withNormal, out MirrorHit h) {
    h.q = ivec2(0);
    if (!(covered && rf.cmoCount > 0u && mirrorHitShare(px, hit.xy, roughness) > 0.0)) return false;
    return findMirrorHit(hit.xyz, p, withNormal, h) && h.m.traceCmos && h.m.roughness <= rf.cmoMaxRoughness;
}

#endif
