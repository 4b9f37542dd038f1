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

void main() {
    vec3 linear = texelFetch(linearTex, ivec2(gl_FragCoord.xy), 0).rgb;
    // NaN or negative input must not poison the image: clamp before the curve.
    linear = max(linear * pc.exposure, vec3(0.0));
    outColor = vec4(srgbEncode(acesFitted(linear)), 1.0);
}
