#version 460
#extension GL_GOOGLE_include_directive : require
// render.tonemap: exposure, ACES fit, sRGB encode, as a fullscreen fragment pass into the
// RGBA8 colour attachment (fullscreen.vert).
#include "common/color.glsl"

layout(set = 0, binding = 0) uniform sampler2D linearTex;

layout(push_constant) uniform TonemapConstants {
    uvec2 size;
    float exposure;
} pc;

layout(location = 0) out vec4 outColor;

// srgbEncode (color.glsl) with 1.055 x^(1/2.4) - 0.055 fitted (minimax on [0.0031308, 1]) by
// a sqrt(x) + b x^(1/4) + c x + d: two square roots instead of a log2/exp2 pair per channel
// (lavapipe expands pow into both), at most 0.1/255 off, so 8-bit values move by at most one.
vec3 srgbEncodeFast(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    vec3 s = sqrt(c);
    vec3 hi = 0.83362857 * s + 0.29819447 * sqrt(s) - 0.05526896 * c - 0.07691579;
    return mix(hi, c * 12.92, lessThanEqual(c, vec3(0.0031308)));
}

void main() {
    vec3 linear = texelFetch(linearTex, ivec2(gl_FragCoord.xy), 0).rgb;
    // NaN or negative input must not poison the image: clamp before the curve.
    linear = max(linear * pc.exposure, vec3(0.0));
    outColor = vec4(srgbEncodeFast(acesFitted(linear)), 1.0);
}
