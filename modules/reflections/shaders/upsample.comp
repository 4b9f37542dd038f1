#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.upsample: joint bilateral upsampling (Kopf et al. 2007) of a half-resolution image
// (the reflection; the method weights in a pass of their own, which the frame graph drops when
// nothing reads them) to full resolution, guided by full-resolution depth and normals.
// Each full pixel weighs the four low-resolution samples around it by their bilinear weight times
// three edge-stopping terms, computed against the sample's own full-resolution pixel (the guide
// says which one it traced, reflections/guide.glsl):
//   plane:    the sample's distance from this pixel's tangent plane, over this pixel's view
//             distance, weighed by max(0, 1 - 50 x): nothing beyond 2% (compact, so that a depth
//             edge leaks nothing at all); near zero on slanted and gently curved surfaces, where
//             depth differences are not edges.
//   normal:   dot(n, n_sample)^32 (a cosine of 0.97 keeps half the weight): creases.
//   material: a non-reflective sample (its reflection is 0) gets no weight, and roughness
//             differences above 0.1 fade the weight (a glossy panel next to a mirror).
// When all four are rejected (thin features, the screen edge), the best-agreeing sample (ranked
// with 1 / (1 + 100 x) for the plane term, which never reaches 0) is taken
// whole: a pixel is never a blend across an edge and never black for lack of weight.
#include "common/camera.glsl"
#include "reflections/shaders/upsample.h"
#include "reflections/shaders/guide.glsl"
#include "reflections/shaders/upsample.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depthTex;   // full: reversed-Z depth (nearest)
layout(set = 0, binding = 1) uniform sampler2D normalTex;  // full: xyz normal, w roughness
layout(set = 0, binding = 2) uniform sampler2D guideTex;   // low: xyz world position, w packGuide()
layout(set = 0, binding = 3) uniform sampler2D lowTex;     // low: the image
layout(set = 0, binding = 4, rgba16f) uniform writeonly image2D fullOut;

vec3 worldAtPixel(vec2 px, float depth) {
    return worldFromDepth(px / up.size.xy, depth, up.invViewProj);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, ivec2(up.size.xy)))) return;
    float depth = texelFetch(depthTex, pixel, 0).r;
    if (depth <= 0.0) {  // the sky reflects nothing (and has no plane to compare with)
        imageStore(fullOut, pixel, vec4(0.0));
        return;
    }
    vec4 normalRough = texelFetch(normalTex, pixel, 0);
    vec3 n = normalize(normalRough.xyz);
    vec3 p = worldAtPixel(vec2(pixel) + 0.5, depth);
    float invDist = 1.0 / max(distance(p, up.eye.xyz), 1e-6);
    imageStore(fullOut, pixel, bilateralUpsample(guideTex, lowTex, ivec2(up.size.zw), pixel, p, n, normalRough.w, invDist));
}
