#version 460
#extension GL_GOOGLE_include_directive : require
// probes.capture_bounce: the specular ambient of reflective surfaces in a probe's face, from the
// previous bake of the probes and then the sky (the fallback chain without screen space), so
// that reflections of reflective surfaces accumulate one bounce per bake. Sky pixels are left
// out (alpha 0): the lookup takes the real sky there. render.lighting left
// this term out for them (kFlagReflective), as it does when the reflections module runs.
// A ray that meets a planar probe's plane from above before the probes' proxy reads the plane's
// ground there (probe.h, PlanarGround): the floor under an object standing on it, which the
// cube's capture point cannot see past the object; a metal floor's reflects the ray (metalGround).
#define PROBES_BUFFER_BINDING 6
#define PROBES_CUBES_BINDING 7
#define PROBES_DISTANCE_BINDING 12
#define PROBES_CAPTURE
#define GROUND_BUFFER_BINDING 10
#define GROUND_IMAGES_BINDING 11
#include "common/brdf.glsl"
#include "common/camera.glsl"
#include "probes/shaders/probes.glsl"
#include "probes/shaders/ground.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;
layout(set = 0, binding = 1) uniform sampler2D albedoTex;    // rgb base colour, a metallic
layout(set = 0, binding = 2) uniform sampler2D normalTex;    // xyz normal, w roughness
layout(set = 0, binding = 3) uniform sampler2D emissiveTex;  // a: flags | material << 2
layout(set = 0, binding = 4) uniform sampler2D litTex;
layout(set = 0, binding = 5) uniform sampler2D dfgTex;       // linear clamp
layout(set = 0, binding = 8) uniform samplerCube envSpecular;
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2D outLit;

layout(push_constant) uniform Push {
    mat4 invViewProj;
    vec4 eye;    // xyz capture point, w the sky's last mip
    uvec4 info;  // xy face size, z probe count (0 on the first bake), w ground count
} pc;

// A mirror ray r that meets a metal floor's ground (g, groundTexel's at `hit`: ground_store.comp's
// marker, rgb F0, a -1 minus the floor's roughness) reflects off the floor and reads the probes
// from there, times its F0; false (radiance unset) for any other ground.
// The cube holds a metal floor as its capture point saw it, reflecting what lies above toward
// the capture point, and under an object standing on the floor it holds the object: a chrome
// sphere standing on the gallery's metal mirror floor showed the sky's blue on its underside, in
// the floor's planar image, where light reflects between floor and sphere (the bounce-converged
// reference shows chrome there; one traced 2 bounces deep shows the split-sum sky, blue too).
// Mirror band against the 4-bounce references: gallery.main 22.27 -> 24.90, floor_grazing
// 21.96 -> 22.52, the rest unchanged (modules/reflections/MEASUREMENTS.md, stop 61). Floors only
// (the plane's normal within 26 degrees of up), where the reflected ray leaves upward into the
// room: on mirror_hall's wall mirror, which faces another across the corridor, the reflected
// ray reads the cube at the facing mirror, whose captured reflection is as wrong for it, and the
// hall lost 4-4.6 dB (a captured mirror's own reflection is the closer guess there).
bool metalGround(vec4 g, vec3 planeNormal, vec3 hit, vec3 r, float roughness, out vec3 radiance) {
    radiance = vec3(0.0);
    if (!(g.a <= -1.0 && roughness < kNarrowLobeMaxRoughness - 0.1 && planeNormal.y >= 0.9)) return false;
    vec3 q = hit + planeNormal * 0.01;
    vec3 r2 = reflect(r, planeNormal);
    float rough2 = max(roughness, -g.a - 1.0);
    float proxy2;
    vec3 skyDir;
    vec4 probe = sampleProbes(pc.info.z, q, planeNormal, r2, rough2, proxy2, skyDir);
    radiance = g.rgb * (probe.rgb + (1.0 - probe.a) * textureLod(envSpecular, skyDir, rough2 * pc.eye.w).rgb);
    return true;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.info.xy))) return;
    vec3 color = texelFetch(litTex, pixel, 0).rgb;
    float depth = texelFetch(depthTex, pixel, 0).r;
    uint flags = uint(texelFetch(emissiveTex, pixel, 0).a);
    if (depth > 0.0 && (flags & 2u) != 0u && (flags & 1u) == 0u) {
        vec2 uv = (vec2(pixel) + 0.5) / vec2(pc.info.xy);
        vec3 p = worldFromDepth(uv, depth, pc.invViewProj);
        vec4 nr = texelFetch(normalTex, pixel, 0);
        vec3 n = normalize(nr.xyz);
        vec3 v = normalize(pc.eye.xyz - p);
        vec3 r = reflect(-v, n);
        float proxy;
        vec3 skyDir;
        vec4 probe = sampleProbes(pc.info.z, p, n, r, nr.w, proxy, skyDir);
        // The ground the ray meets, fetched once: a metal floor's reflects the ray, any other
        // lies over the probes.
        vec3 planeNormal;
        float t;
        vec4 ground = groundTexel(pc.info.w, p, r, nr.w, groundLimit(proxy), planeNormal, t);
        vec3 radiance;
        if (!metalGround(ground, planeNormal, p + r * t, r, nr.w, radiance)) {
            probe = groundOver(ground, nr.w, probe);
            radiance = probe.rgb + (1.0 - probe.a) * textureLod(envSpecular, skyDir, nr.w * pc.eye.w).rgb;
        }
        vec4 albedo = texelFetch(albedoTex, pixel, 0);
        vec2 dfg = textureLod(dfgTex, vec2(clamp(dot(n, v), 0.0, 1.0), nr.w), 0.0).rg;
        color += radiance * (specularF0(albedo.rgb, albedo.a) * dfg.x + dfg.y);
    }
    // The sky is infinitely far: the probe leaves it out (rgb 0, alpha 0) and the lookup takes the
    // sky itself along the unprojected ray there (sampleProbes), which no box or sphere proxy
    // can place right. Alpha is the probe's coverage; rgb is premultiplied by it.
    imageStore(outLit, pixel, depth > 0.0 ? vec4(color, 1.0) : vec4(0.0));
}
