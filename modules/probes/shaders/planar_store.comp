#version 460
#extension GL_GOOGLE_include_directive : require
// probes.planar_store: a planar probe's image from its mirrored view. rgb: the lit view with the
// specular ambient of reflective surfaces (probes.capture_bounce) and the sky where nothing was
// drawn (a mirror shows the sky exactly, unlike a cube's proxy); alpha: the distance from where
// the mirrored ray crosses the plane to the surface it sees (m), 65504 (the half float's largest,
// the reflections module's kSkyDistance) for the sky. The lookup sizes a glossy footprint and
// refracts a bumped normal's ray by it (planar.glsl), and the temporal pass reprojects by it.
#include "common/camera.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;
layout(set = 0, binding = 1) uniform sampler2D faceTex;  // probes.capture_bounce: alpha 0 at the sky
layout(set = 0, binding = 2) uniform sampler2D litTex;   // render.lighting: the sky's colour there
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D outImage;

layout(push_constant) uniform Push {
    mat4 invViewProj;  // the mirrored camera's
    vec4 eye;          // xyz the mirrored eye
    vec4 plane;        // xyz unit normal, w offset
    uvec4 info;        // xy the image's size
} pc;

const float kSkyDistance = 65504.0;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.info.xy))) return;
    float depth = texelFetch(depthTex, pixel, 0).r;
    vec4 result = vec4(texelFetch(litTex, pixel, 0).rgb, kSkyDistance);
    if (depth > 0.0) {
        vec2 uv = (vec2(pixel) + 0.5) / vec2(pc.info.xy);
        vec3 p = worldFromDepth(uv, depth, pc.invViewProj);
        // The mirrored eye is behind the plane (se < 0), the surface in front of it (sp > 0): the
        // ray crosses the plane at the fraction -se / (sp - se) of the way.
        float se = dot(pc.plane.xyz, pc.eye.xyz) + pc.plane.w;
        float sp = dot(pc.plane.xyz, p) + pc.plane.w;
        float f = clamp(-se / max(sp - se, 1e-6), 0.0, 1.0);
        result = vec4(texelFetch(faceTex, pixel, 0).rgb, min(distance(p, pc.eye.xyz) * (1.0 - f), kSkyDistance));
    }
    imageStore(outImage, pixel, result);
}
