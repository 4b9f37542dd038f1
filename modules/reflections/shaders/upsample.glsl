// The joint bilateral upsampling of `lowTex` (lowSize texels, the half-size grid whose guide is
// `guideTex`) at full pixel `pixel`, a surface point p with normal n and G-buffer roughness
// `roughness` at 1 / invDist from the eye. Shared by reflections.upsample and reflections.refresh.
// Needs guide.glsl.
#ifndef SPECULUM_REFLECTIONS_UPSAMPLE_GLSL
#define SPECULUM_REFLECTIONS_UPSAMPLE_GLSL

// Also returns the per-channel box (lo, hi) of the four low-resolution samples it weighed, which
// reflections.refresh clips a moving pixel's history to: the same four texels, fetched once.
vec4 bilateralUpsampleBox(sampler2D guideTex, sampler2D lowTex, ivec2 lowSize, ivec2 pixel, vec3 p, vec3 n,
                          float roughness, float invDist, out vec3 lo, out vec3 hi) {
    // The low-resolution grid: sample i sits at full position 2 i + 1 (its 2x2's centre).
    vec2 lowPos = (vec2(pixel) + 0.5) * 0.5 - 0.5;
    ivec2 base = ivec2(floor(lowPos));
    vec2 f = lowPos - vec2(base);
    ivec2 lowMax = lowSize - 1;
    vec4 sum = vec4(0.0);
    float total = 0.0;
    float bestAgree = -1.0;
    ivec2 bestSample = clamp(base, ivec2(0), lowMax);
    // The pixel its own half pixel traced (the guide's index in the 2x2) keeps that value: a
    // quarter of the pixels are then the full-resolution ones. Blending it with the neighbours
    // as every other pixel is blurred the curved mirrors that half resolution loses most on
    // (mirror band +0.02 to +0.26 dB at 320x180 and 640x360 on gallery, closed_room and
    // cornell_mirrors: MEASUREMENTS.md, issue 23, "the traced pixel keeps its value").
    bool traced = false;
    vec4 tracedValue = vec4(0.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, i >> 1);
        ivec2 s = clamp(base + o, ivec2(0), lowMax);
        vec4 guide = texelFetch(guideTex, s, 0);
        GuideSample g = unpackGuide(guide.w);
        float plane = abs(dot(n, guide.xyz - p)) * invDist;
        // dot^32 by five squarings, not pow() (a log and an exp per lane on a CPU driver).
        float c = max(dot(n, g.normal), 0.0);
        c *= c;
        c *= c;
        c *= c;
        c *= c;
        c *= c;
        float others = c * clamp(1.0 - (abs(g.roughness - roughness) - 0.1) * 10.0, 0.0, 1.0) *
                       (g.reflective ? 1.0 : 0.0);
        // The fallback's ranking only needs an order that never reaches 0: 1 / (1 + 100 x).
        float agree = others / (1.0 + plane * 100.0);
        vec2 b = mix(1.0 - f, f, vec2(o));
        float w = b.x * b.y * max(1.0 - plane * 50.0, 0.0) * others;
        vec4 c4 = texelFetch(lowTex, s, 0);
        bool own = s * 2 + ivec2(g.index & 1, g.index >> 1) == pixel;
        traced = traced || own;
        tracedValue = own ? c4 : tracedValue;
        lo = i == 0 ? c4.rgb : min(lo, c4.rgb);
        hi = i == 0 ? c4.rgb : max(hi, c4.rgb);
        sum += w * c4;
        total += w;
        if (agree > bestAgree) {
            bestAgree = agree;
            bestSample = s;
        }
    }
    return traced ? tracedValue : total > 1e-6 ? sum / total : texelFetch(lowTex, bestSample, 0);
}

vec4 bilateralUpsample(sampler2D guideTex, sampler2D lowTex, ivec2 lowSize, ivec2 pixel, vec3 p, vec3 n,
                       float roughness, float invDist) {
    vec3 lo, hi;
    return bilateralUpsampleBox(guideTex, lowTex, lowSize, pixel, p, n, roughness, invDist, lo, hi);
}

#endif
