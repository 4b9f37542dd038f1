// The fallback chain's per-pixel decisions, shared by reflections.classify, trace, cmo_trace,
// resolve and lookup_full so that a tile list and the pass that runs on it can never disagree.
// Include after common.glsl, material.glsl and probes/shaders/planar.glsl (and
// probes/shaders/probes.glsl and ground.glsl for probesAndSky).
#ifndef SPECULUM_REFLECTIONS_CHAIN_GLSL
#define SPECULUM_REFLECTIONS_CHAIN_GLSL

// A planar probe takes the pixel whole (its mirrored image; reflections.resolve).
bool planarServes(float depth, PixelMaterial m, vec3 p, vec3 n) {
    return rf.planarCount > 0u && depth > 0.0 && planarShare(m.roughness) >= 1.0 &&
           planarAt(rf.planarCount, p, n, rfm.eye) >= 0;
}

// The pixel's reflection may be traced through the CMOs (what screen space leaves of it).
bool inCmoBand(float depth, PixelMaterial m, bool planar) {
    return rf.cmoCount > 0u && depth > 0.0 && m.reflective && m.traceCmos && m.roughness <= rf.cmoMaxRoughness &&
           !planar;
}

// Whether screen space alone covers this pixel (resolve.comp's coverage in `hit` mode is 1, less
// a glossy cone's tail, coneTail, which the probes' prefiltered lookups answer: a CMO traces the
// mirror ray, not a lobe's tail): then nothing is left for the CMOs. r: the mirror ray.
bool screenCovers(vec4 hit, vec3 p, vec3 r, vec3 v, PixelMaterial m) {
    if (!(hit.z > 0.0) || rf.coverageMode != 0u || !m.screenSpace) return false;
    float fades = edgeFade(hit.xy) * cameraFade(dot(r, v)) * distanceFade(distance(worldAt(hit.xy, hit.z), p)) *
                  clamp((m.maxScreenSpace - m.roughness) / 0.1, 0.0, 1.0);
    return fades >= 1.0;
}

#ifdef SPECULUM_PROBES_GLSL
// What the chain gives past screen space and the CMOs, the planar probe aside: the local probes
// with the planar probes' grounds over them (probes/shaders/ground.glsl), then the sky for what
// they leave (reflections.resolve, and reflections.lookup_full, which must give the same bits).
// Needs the includer's envSpecular (the prefiltered sky cube).
vec3 probesAndSky(vec3 p, vec3 n, vec3 r, float roughness, out vec4 probe, out float proxyDistance) {
    vec3 skyDir;
    probe = sampleProbes(rf.probeCount, p, n, r, roughness, proxyDistance, skyDir);
    // The grounds serve narrow lobes only (ground.glsl): compiled out with the march.
    if (PROBES_NARROW_LOBES) probe = groundOverProbes(rf.groundCount, p, r, roughness, probe, proxyDistance);
    vec3 sky = textureLod(envSpecular, skyDir, roughness * rf.envMaxMip).rgb;
    return probe.rgb + (1.0 - probe.a) * sky;
}
#endif

#endif
