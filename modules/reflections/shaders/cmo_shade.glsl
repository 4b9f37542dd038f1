// A CMO hit shaded for the ray that found it (shadeHit), shared by reflections.cmo_trace and
// reflections.hit_reuse so that the two give a hit the same value. Include after common.glsl,
// relight.glsl and probes/shaders/cmo.glsl, with CMO_RADIANCE_BINDING defined (the radiance as a
// trilinear cube array, for glossy footprints).
#ifndef SPECULUM_REFLECTIONS_CMO_SHADE_GLSL
#define SPECULUM_REFLECTIONS_CMO_SHADE_GLSL

layout(set = 0, binding = CMO_RADIANCE_BINDING) uniform samplerCubeArray cmoRadiance;

// The hit's radiance toward the viewer of the reflection: what the CMO captured (lit for the
// CMO's own direction), with the lights' direct terms moved to the reflected ray's direction
// (relight.glsl). Glossy rays read
// the radiance mips at the cone's footprint `cone` (world width at the hit). `mirror`: the hit
// reflects again (main's self-reflection loop) where its material is mirror-masked, or where it
// is a reflective metal smoother than reflections.hit_reflect_max_roughness. A metal's radiance
// is all reflection, so what the CMO captured of it (its reflection toward the CMO's centre) says
// nothing about the ray's direction: screen space's mirror hits had the same error (resolve.comp,
// mirrorHit). A dielectric's radiance is mostly its own diffuse light, which the capture holds
// and a ray reflected again would drop, so it keeps the captured value. Treating cornell_mirrors'
// unmasked chrome this way scored sphere_close 18.04 -> 18.70 dB and blob_close 19.05 -> 20.25
// in the mirror band (MEASUREMENTS.md, issue 24, 2026-12-06).
vec3 shadeHit(CmoRecord c, vec3 hp, vec3 dir, float cone, out bool mirror, out vec3 n, out vec3 f0) {
    vec3 u = hp - c.center.xyz;
    ivec3 texel = cmoTexel(c, u);
    ivec3 at = ivec3(texel.xy, int(c.params.x) + texel.z);
    int base = int(c.params.y);
    vec4 lit = texelFetch(cmoLayers, at, base);
    vec4 nr = texelFetch(cmoAttr, at, base);
    vec4 albedo = texelFetch(cmoAlbedo, at, base);
    float sun;
    bool masked, reflective;
    cmoUnpackFlags(lit.a, sun, masked, reflective);
    mirror = masked || (reflective && albedo.a >= 0.5 && nr.w < rf.hitReflectMaxRoughness);
    n = normalize(nr.xyz);
    f0 = specularF0(albedo.rgb, albedo.a);
    vec3 delta = movedDirect(hp, n, -dir, normalize(-u), albedo.rgb, albedo.a, nr.w, sun);
    // Filtered at the refined hit's direction, a mirror's too (mip 0 is bilinear): the hit's
    // place is continuous (cmoRefine), and the texel it falls in (nearest) put an edge of the room
    // a texel off: mirror_floor's floor reflected the ceiling where the wall's top 3 mm lay
    // (issue 24, "sub-pixel registration"; MEASUREMENTS.md).
    float texelWorld = length(u) * c.params.w;
    float mip = log2(max(cone / max(texelWorld, 1e-6), 1.0));
    float top = float(base) + c.params.z - 1.0;
    vec3 captured = textureLod(cmoRadiance, vec4(u, c.params.x / 6.0), min(float(base) + mip, top)).rgb;
    return max(captured + delta, vec3(0.0));
}

// The first hit of the ray origin + t dir (leaving a surface with normal `normal`) on the CMOs in
// their order: its CMO's index (-1: none) and t. `unresolved`: some CMO left the ray unresolved.
// With reflections.cmo_unresolved=pass_behind, if all left it unresolved, the first once more with
// the ray taken to pass behind what hid it (cmo.glsl, passBehind): a thin pillar hides a strip of
// wall from a CMO, and the local probes would paint the pillar there again.
int cmoFirstHit(vec3 origin, vec3 normal, vec3 dir, bool linear, inout int iterations, out float tHit,
                out bool unresolved) {
    int found = -1;
    tHit = 0.0;
    unresolved = false;
    int maxIterations = int(rf.cmoMaxIterations);
    for (uint k = 0u; k <= rf.cmoCount && found < 0; ++k) {
        bool last = k == rf.cmoCount;
        if (last && !(unresolved && rf.cmoPassBehind != 0u)) break;
        uint i = last ? 0u : k;
        CmoRecord c = cmos[i];
        vec3 o = origin - c.center.xyz;
        float th;
        int status = linear ? cmoTraceLinear(c, o, dir, normal, rf.cmoMaxDistance, rf.cmoLinearStep, rf.cmoThickness,
                                             maxIterations, last, iterations, th)
                            : cmoTraceHierarchical(c, o, dir, normal, rf.cmoMaxDistance, rf.cmoThickness, maxIterations,
                                                   last, iterations, th);
        if (status == kCmoHit) {
            found = int(i);
            tHit = th;
        }
        unresolved = unresolved || status == kCmoUnresolved;
    }
    return found;
}

// Self-reflection: a hit at hp on a mirror (shadeHit's `mirror`; normal hn, F0 f0) that the ray
// `dir` reached with radiance `shaded` (what the CMO captured there, the answer where the
// reflected ray finds nothing) reflects again, weighed by its Fresnel term, up to
// reflections.cmo_bounces in all. `travelled`: the ray's length so far (the cone's footprint);
// `bounces`: how many it took.
vec3 cmoSelfReflections(vec3 hp, vec3 hn, vec3 f0, vec3 dir, vec3 shaded, float travelled, float coneSlope,
                        bool linear, inout int iterations, inout float bounces) {
    int maxBounces = int(rf.cmoBounces);
    vec3 fallback = shaded;
    vec3 throughput = F_Schlick(f0, max(dot(hn, -dir), 0.0));
    vec3 origin = hp, normal = hn;
    dir = reflect(dir, hn);
    bounces = 1.0;
    for (int bounce = 1; bounce <= maxBounces; ++bounce) {
        float tHit;
        bool unresolved;
        int found = cmoFirstHit(origin, normal, dir, linear, iterations, tHit, unresolved);
        if (found < 0) return fallback;
        CmoRecord c = cmos[found];
        vec3 p2 = origin + dir * tHit;
        travelled += tHit;
        bool mirror;
        vec3 n2, f02;
        vec3 s2 = shadeHit(c, p2, dir, coneSlope * travelled, mirror, n2, f02);
        if (dot(n2, dir) > 0.05) return fallback;  // seen from behind, as at the first hit
        if (mirror && bounce < maxBounces) {
            fallback = throughput * s2;
            throughput *= F_Schlick(f02, max(dot(n2, -dir), 0.0));
            origin = p2;
            normal = n2;
            dir = reflect(dir, n2);
            bounces = float(bounce + 1);
            continue;
        }
        return throughput * s2;
    }
    return fallback;
}

#endif
