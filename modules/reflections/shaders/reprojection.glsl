// Where a pixel's history was, for the passes that keep one (reflections.temporal and
// reflections.refresh): by the surface (its motion vector, checked against the previous depth,
// normal and roughness) and by the reflected point (its mirror image behind the surface at the
// reflected distance; the sky's is a direction). Include after common.glsl; the including shader
// declares motionTex, historyDepth and historyNormal (xyz normal, w roughness, < 0 none).
#ifndef SPECULUM_REFLECTIONS_REPROJECTION_GLSL
#define SPECULUM_REFLECTIONS_REPROJECTION_GLSL

bool insideUV(vec2 uv) {
    return all(greaterThanEqual(uv, vec2(0.0))) && all(lessThan(uv, vec2(1.0)));
}

// The previous frame saw a surface of this normal (cosine above minCos) and roughness (within
// 0.1) at prevPixel.
bool sameSurfaceThere(ivec2 prevPixel, vec3 n, float roughness, float minCos) {
    vec4 prev = texelFetch(historyNormal, prevPixel, 0);
    return prev.w >= 0.0 && dot(prev.xyz, n) > minCos && abs(prev.w - roughness) < 0.1;
}

// The surface's previous position (prevUV, prevPixel); true where the previous frame saw this
// surface there: depth within 2% of what the camera's motion predicts, normal within 25 degrees.
bool surfaceHistory(ivec2 pixel, vec3 p, vec3 n, float roughness, out vec2 prevUV, out ivec2 prevPixel) {
    vec2 uv = (vec2(pixel) + 0.5) * rf.size.zw;
    prevUV = uv - texelFetch(motionTex, pixel, 0).rg;
    vec4 prevClip = rfm.prevViewProj * vec4(p, 1.0);
    float expected = linearDepth(prevClip.z / prevClip.w);
    prevPixel = ivec2(floor(prevUV * rf.size.xy));
    return insideUV(prevUV) && abs(linearDepth(texelFetch(historyDepth, prevPixel, 0).r) - expected) < 0.02 * expected &&
           sameSurfaceThere(prevPixel, n, roughness, 0.9);
}

// The reflected point's previous pixel for a reflection `dist` away (kSkyDistance: the sky);
// true where the previous frame saw this surface there (normal within 18 degrees).
bool reflectedHistory(vec3 p, float dist, vec3 n, float roughness, out ivec2 prevPixel) {
    prevPixel = ivec2(0);
    if (!(dist > 0.0)) return false;
    vec3 viewDir = normalize(p - rfm.eye);
    vec4 virt = dist >= kSkyDistance ? vec4(viewDir, 0.0) : vec4(p + viewDir * dist, 1.0);
    vec4 clip = rfm.prevViewProj * virt;
    vec2 prevV = clip.w > 0.0 ? ndcToUV(clip.xy / clip.w) : vec2(-1.0);
    prevPixel = ivec2(floor(prevV * rf.size.xy));
    return insideUV(prevV) && sameSurfaceThere(prevPixel, n, roughness, 0.95);
}

#endif
