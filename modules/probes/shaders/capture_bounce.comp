#version 460
#extension GL_GOOGLE_include_directive : require
// probes.capture_bounce: the specular ambient of reflective surfaces in a probe's face, from the
// previous bake of the probes and then the sky (the fallback chain without screen space), so
// that reflections of reflective surfaces accumulate one bounce per bake. Sky pixels are left
// out (alpha 0): the lookup takes the real sky there. render.lighting left
// this term out for them (kFlagReflective), as it does when the reflections module runs.
// A ray that meets a planar probe's plane from above before the probes' proxy reads the plane's
// ground there (probe.h, PlanarGround): the floor under an object standing on it, which the
// cube's capture point cannot see past the object.
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
        vec3 sky = textureLod(envSpecular, skyDir, nr.w * pc.eye.w).rgb;
        probe = groundOverProbes(pc.info.w, p, r, nr.w, probe, proxy);
        vec3 radiance = probe.rgb + (1.0 - probe.a) * sky;
        vec4 albedo = texelFetch(albedoTex, pixel, 0);
        vec2 dfg = textureLod(dfgTex, vec2(clamp(dot(n, v), 0.0, 1.0), nr.w), 0.0).rg;
        color += radiance * (specularF0(albedo.rgb, albedo.a) * dfg.x + dfg.y);
    }
    // The sky is infinitely far: the probe leaves it out (rgb 0, alpha 0) and the lookup takes the
    // sky itself along the unprojected ray there (sampleProbes), which no box or sphere proxy
    // can place right. Alpha is the probe's coverage; rgb is premultiplied by it.
    imageStore(outLit, pixel, depth > 0.0 ? vec4(color, 1.0) : vec4(0.0));
}
