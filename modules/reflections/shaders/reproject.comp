#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.reproject: level 0 of the colour pyramid. Each pixel takes the previous frame's
// final image (reflections included, so reflections of reflections accumulate over frames,
// Uludag 4.6.4) at the pixel's previous position, when the previous depth there agrees;
// otherwise, and on the first frame, this frame's lit image.
#include "reflections/shaders/common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D depthTex;
layout(set = 0, binding = 2) uniform sampler2D motionTex;
layout(set = 0, binding = 3) uniform sampler2D litTex;
layout(set = 0, binding = 4) uniform sampler2D historyColor;  // bilinear
layout(set = 0, binding = 5) uniform sampler2D historyDepth;  // texelFetch only
layout(set = 0, binding = 6, rgba16f) uniform writeonly image2D dst;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, ivec2(rf.size.xy)))) return;
    vec3 current = texelFetch(litTex, pixel, 0).rgb;
    vec3 color = current;
    if (rf.historyValid != 0u && rf.multiBounce != 0u) {
        vec2 uv = (vec2(pixel) + 0.5) * rf.size.zw;
        float depth = texelFetch(depthTex, pixel, 0).r;
        vec2 prevUV;
        float expectedDepth;
        if (depth > 0.0) {
            // Motion vectors carry object motion too; the expected previous depth is the
            // camera's (static geometry), which is what the depth test below guards.
            prevUV = uv - texelFetch(motionTex, pixel, 0).rg;
            vec4 prevClip = rfm.prevViewProj * vec4(worldAt(vec2(pixel) + 0.5, depth), 1.0);
            expectedDepth = prevClip.z / prevClip.w;
        } else {
            vec3 dir = viewRayDirection(uv, rfm.invViewProj);
            vec4 prevClip = rfm.prevViewProj * vec4(dir, 0.0);
            prevUV = prevClip.w > 0.0 ? ndcToUV(prevClip.xy / prevClip.w) : vec2(-1.0);
            expectedDepth = 0.0;
        }
        ivec2 prevPixel = ivec2(floor(prevUV * rf.size.xy));
        bool inside = all(greaterThanEqual(prevUV, vec2(0.0))) && all(lessThan(prevUV, vec2(1.0)));
        if (inside) {
            float stored = texelFetch(historyDepth, prevPixel, 0).r;
            bool sameSurface = expectedDepth <= 0.0
                ? stored <= 0.0
                : abs(linearDepth(stored) - linearDepth(expectedDepth)) < 0.02 * linearDepth(expectedDepth);
            vec3 history = textureLod(historyColor, prevUV, 0.0).rgb;
            if (sameSurface && finite3(history)) color = history;
        }
    }
    if (!finite3(color)) color = vec3(0.0);
    imageStore(dst, pixel, vec4(max(color, vec3(0.0)), 1.0));
}
