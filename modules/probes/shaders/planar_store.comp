#version 460
#extension GL_GOOGLE_include_directive : require
// probes.planar_store: a planar probe's image from its mirrored view (the crop of it that its
// rectangle covers on screen, written where the whole view would have it in the layer). rgb: the lit view with the
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
    vec4 eye;          // xyz the mirrored eye, w the crop's offset in the layer: x + 4096 y
    vec4 plane;        // xyz unit normal, w offset
    vec4 axisX;        // the rectangle's x axis over its half width, w its offset: |dot(q, xyz) + w| <= 1 inside
    vec4 axisZ;        // the same along its depth
} pc;

const float kSkyDistance = 65504.0;

// Whether the texel's ray crosses the plane inside the probe's rectangle (1% margin), and the
// point it sees (p) and the fraction of the way from the eye where it crosses (f). Cheap: one
// depth fetch, so the dilation below can test its eight neighbours without their colours (it
// fetched all nine texels' colours and the sky before: 12.3 ms at 480x270 on closed_room, most
// texels outside the floor's rectangle).
bool crossesInside(ivec2 pixel, ivec2 size, out float depth, out vec3 p, out vec3 skyDir, out float f) {
    depth = texelFetch(depthTex, pixel, 0).r;
    vec2 uv = (vec2(pixel) + 0.5) / vec2(size);
    // The sky has no finite position: a point along its ray, from the eye through depth 1, the
    // oblique near plane (the mirror, 2 mm in front), which every ray that crosses the mirror in
    // front of the eye meets there (the rest cross behind it and are outside, below).
    skyDir = normalize(worldFromDepth(uv, 1.0, pc.invViewProj) - pc.eye.xyz);
    p = depth > 0.0 ? worldFromDepth(uv, depth, pc.invViewProj) : pc.eye.xyz + skyDir;
    // The mirrored eye is behind the plane (se < 0), the surface in front of it (sp > 0): the
    // ray crosses the plane at the fraction -se / (sp - se) of the way.
    float se = dot(pc.plane.xyz, pc.eye.xyz) + pc.plane.w;
    float sp = dot(pc.plane.xyz, p) + pc.plane.w;
    f = -se / max(sp - se, 1e-6);
    vec3 q = mix(pc.eye.xyz, p, f);
    return sp > se && abs(dot(q, pc.axisX.xyz) + pc.axisX.w) <= 1.01 && abs(dot(q, pc.axisZ.xyz) + pc.axisZ.w) <= 1.01;
}

// The texel's radiance and reflected distance. A branch, not a select: a group of lanes that
// all see surfaces skips the sky's cube lookup.
vec4 texelValue(ivec2 pixel, float depth, vec3 p, vec3 skyDir, float f) {
    if (depth > 0.0)
        return vec4(texelFetch(faceTex, pixel, 0).rgb, min(distance(p, pc.eye.xyz) * (1.0 - clamp(f, 0.0, 1.0)), kSkyDistance));
    return vec4(textureLod(envSpecular, skyDir, 0.0).rgb, kSkyDistance);
}

// Whether each texel of the workgroup's 8x8 block and its one-texel border crosses inside: 100
// tests a workgroup where each texel asking its eight neighbours made 576.
shared bool insideTile[10 * 10];

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(depthTex, 0);
    ivec2 corner = ivec2(gl_WorkGroupID.xy) * 8 - 1;
    for (uint i = gl_LocalInvocationIndex; i < 100u; i += 64u) {
        float nd, nf;
        vec3 np, ns;
        ivec2 q = clamp(corner + ivec2(i % 10u, i / 10u), ivec2(0), size - 1);
        insideTile[i] = crossesInside(q, size, nd, np, ns, nf);
    }
    barrier();
    if (any(greaterThanEqual(pixel, size))) return;
    ivec2 local = ivec2(gl_LocalInvocationID.xy) + 1;
    // Which of the eight neighbours cross inside (bit k: the k-th in row order, the centre left
    // out); only an outside texel asks. Clamped at the image's edge as the border is.
    uint insideNeighbours = 0u;
    if (!insideTile[local.y * 10 + local.x])
        for (int k = 0; k < 9; ++k) {
            ivec2 t = local + ivec2(k % 3 - 1, k / 3 - 1);
            if (k != 4 && insideTile[t.y * 10 + t.x]) insideNeighbours |= 1u << k;
        }
    vec4 result;
    if (insideNeighbours == 0u) {
        float depth, f;
        vec3 p, skyDir;
        crossesInside(pixel, size, depth, p, skyDir, f);
        result = texelValue(pixel, depth, p, skyDir, f);
    } else {
        vec4 sum = vec4(0.0);
        float n = 0.0;
        for (int k = 0; k < 9; ++k)
            if ((insideNeighbours & (1u << k)) != 0u) {
                ivec2 q = clamp(pixel + ivec2(k % 3 - 1, k / 3 - 1), ivec2(0), size - 1);
                float nd, nf;
                vec3 np, ns;
                crossesInside(q, size, nd, np, ns, nf);
                sum += texelValue(q, nd, np, ns, nf);
                n += 1.0;
            }
        result = sum / n;
    }
    uint offset = uint(pc.eye.w);
    imageStore(outImage, pixel + ivec2(offset % 4096u, offset / 4096u), result);
}
