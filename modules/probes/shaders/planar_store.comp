#version 460
#extension GL_GOOGLE_include_directive : require
// probes.planar_store: a planar probe's image from its mirrored view. rgb: the lit view with the
// specular ambient of reflective surfaces (probes.capture_bounce) and the sky where nothing was
// drawn (a mirror shows the sky exactly, unlike a cube's proxy); alpha: the distance from where
// the mirrored ray crosses the plane to the surface it sees (m), 65504 (the half float's largest,
// the reflections module's kSkyDistance) for the sky. The lookup sizes a glossy footprint and
// bends a bumped normal's ray by it (planar.glsl), and the temporal pass reprojects by it.
//
// A texel whose ray crosses the plane outside the probe's rectangle shows what lies behind the
// mirror's border (clipped: the sky, or nothing), which no served pixel should see; but a served
// pixel at the border (a floor meeting a wall) reads the texels around it, and at the planar
// image's half resolution those were sky: a dashed bright line along every seam. Such a texel
// takes the mean of its neighbours whose rays do cross inside (a one-texel dilation).
#include "common/camera.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;
layout(set = 0, binding = 1) uniform sampler2D faceTex;  // probes.capture_bounce: alpha 0 at the sky
// The sky along the mirrored ray where nothing was drawn. Not render.lighting's sky: it takes the
// ray from a point at depth 0.5, which the oblique projection can put beyond infinity (its far
// plane is no longer at depth 0), and there the direction flips: a mirror floor under an open sky
// showed the environment's ground (failure_cases: 9.8 dB against 14.0 without the probe).
layout(set = 0, binding = 2) uniform samplerCube envSpecular;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D outImage;

layout(push_constant) uniform Push {
    mat4 invViewProj;  // the mirrored camera's
    vec4 eye;          // xyz the mirrored eye
    vec4 plane;        // xyz unit normal, w offset
    vec4 axisX;        // the rectangle's x axis over its half width, w its offset: |dot(q, xyz) + w| <= 1 inside
    vec4 axisZ;        // the same along its depth
} pc;

const float kSkyDistance = 65504.0;

// The texel's radiance and reflected distance; false when its ray crosses the plane outside the
// probe's rectangle (1% margin).
bool texel(ivec2 pixel, ivec2 size, out vec4 result) {
    float depth = texelFetch(depthTex, pixel, 0).r;
    vec2 uv = (vec2(pixel) + 0.5) / vec2(size);
    // The sky has no finite position: a point along its ray, from the eye through depth 1, the
    // oblique near plane (the mirror, 2 mm in front), which every ray that crosses the mirror in
    // front of the eye meets there (the rest cross behind it and are outside, below).
    vec3 skyDir = normalize(worldFromDepth(uv, 1.0, pc.invViewProj) - pc.eye.xyz);
    vec3 p = depth > 0.0 ? worldFromDepth(uv, depth, pc.invViewProj) : pc.eye.xyz + skyDir;
    // The mirrored eye is behind the plane (se < 0), the surface in front of it (sp > 0): the
    // ray crosses the plane at the fraction -se / (sp - se) of the way.
    float se = dot(pc.plane.xyz, pc.eye.xyz) + pc.plane.w;
    float sp = dot(pc.plane.xyz, p) + pc.plane.w;
    float f = -se / max(sp - se, 1e-6);
    vec3 q = mix(pc.eye.xyz, p, f);
    bool inside = sp > se && abs(dot(q, pc.axisX.xyz) + pc.axisX.w) <= 1.01 && abs(dot(q, pc.axisZ.xyz) + pc.axisZ.w) <= 1.01;
    result = depth > 0.0 ? vec4(texelFetch(faceTex, pixel, 0).rgb,
                                min(distance(p, pc.eye.xyz) * (1.0 - clamp(f, 0.0, 1.0)), kSkyDistance))
                         : vec4(textureLod(envSpecular, skyDir, 0.0).rgb, kSkyDistance);
    return inside;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(depthTex, 0);
    if (any(greaterThanEqual(pixel, size))) return;
    vec4 result;
    if (!texel(pixel, size, result)) {
        vec4 sum = vec4(0.0);
        float n = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                ivec2 q = clamp(pixel + ivec2(dx, dy), ivec2(0), size - 1);
                vec4 c;
                if ((dx != 0 || dy != 0) && texel(q, size, c)) {
                    sum += c;
                    n += 1.0;
                }
            }
        if (n > 0.0) result = sum / n;
    }
    imageStore(outImage, pixel, result);
}
