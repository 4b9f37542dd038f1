#version 460
#extension GL_GOOGLE_include_directive : require
// render.tonemap: exposure, ACES fit, sRGB encode.
#include "common/color.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D linearTex;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D outColor;

layout(push_constant) uniform TonemapConstants {
    uvec2 size;
    float exposure;
} pc;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    vec3 linear = texelFetch(linearTex, pixel, 0).rgb;
    // NaN or negative input must not poison the image: clamp before the curve.
    linear = max(linear * pc.exposure, vec3(0.0));
    imageStore(outColor, pixel, vec4(srgbEncode(acesFitted(linear)), 1.0));
}
