// Half resolution's guide (reflections.resolution = half): which full-resolution pixel each
// half-resolution pixel traces, and what the upsampler needs to weigh it. The trace picks the
// pixel and writes the guide (chooseGuidePixel, packGuide: one pass, so that the chosen pixel's
// depth, normal and material are fetched once); the resolve (guidePixel() of common.glsl) and the
// upsampler (unpackGuide) read it.
//
// The choice: of the 2x2 pixels under a half pixel, reflective ones first, then, in a
// checkerboard, the closest and the farthest depth: at a silhouette both surfaces keep samples
// on their side, so that the joint bilateral upsampling finds a match on either side of the edge
// (always the closest would leave the background's pixels next to an edge only foreground
// samples: a halo).
//
// The guide (RGBA32F): xyz the world position of the chosen pixel (the upsampler then
// reconstructs one position per pixel, not five: a matrix product per sample cost it a third of
// its time), and w = +-(1 + bits), positive when the pixel reflects, with
// bits = index in the 2x2 (2 bits) | G-buffer roughness (6 bits) << 2 | octahedral normal
// (7 + 7 bits) << 8: 22 bits, so that the float holds them exactly (24-bit mantissa). The
// upsampler then reads each sample's normal and roughness with its position in one fetch
// instead of two (16 -> 12 fetches per full-resolution pixel). 7-bit octahedral normals are
// within about 1.5 degrees, which moves dot(n, n_sample)^32 by about 1%.
#ifndef SPECULUM_REFLECTIONS_GUIDE_GLSL
#define SPECULUM_REFLECTIONS_GUIDE_GLSL

vec2 octEncode(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 p = n.z >= 0.0 ? n.xy : (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return p * 0.5 + 0.5;
}

vec3 octDecode(vec2 e) {
    vec2 f = e * 2.0 - 1.0;
    vec3 n = vec3(f, 1.0 - abs(f.x) - abs(f.y));
    float t = clamp(-n.z, 0.0, 1.0);
    n.xy += vec2(n.x >= 0.0 ? -t : t, n.y >= 0.0 ? -t : t);
    return normalize(n);
}

float packGuide(int index, bool reflective, float roughness, vec3 n) {
    // floor(x + 0.5), not round(): GLSL lets round() pick either way at .5.
    uvec2 o = uvec2(floor(clamp(octEncode(normalize(n)), 0.0, 1.0) * 127.0 + 0.5));
    uint r = uint(floor(clamp(roughness, 0.0, 1.0) * 63.0 + 0.5));
    uint bits = uint(index) | (r << 2) | (o.x << 8) | (o.y << 15);
    return float(1u + bits) * (reflective ? 1.0 : -1.0);
}

struct GuideSample {
    int index;
    bool reflective;
    float roughness;
    vec3 normal;
};

GuideSample unpackGuide(float w) {
    uint bits = uint(abs(w)) - 1u;
    GuideSample g;
    g.index = int(bits & 3u);
    g.reflective = w > 0.0;
    g.roughness = float((bits >> 2) & 63u) / 63.0;
    g.normal = octDecode(vec2(float((bits >> 8) & 127u), float((bits >> 15) & 127u)) / 127.0);
    return g;
}

#ifdef SPECULUM_REFLECTIONS_GUIDE_CHOOSE
// The pixel a half-resolution pixel traces, with its depth, normal and roughness and flags (as
// fetched: the caller reuses them). Needs common.glsl, material.glsl and the caller's `hiz`,
// `normalTex` and `emissiveTex` (bindings 1-3 of the trace).
struct GuideChoice {
    int index;  // in the 2x2, x + 2 y
    ivec2 pixel;
    float depth;
    vec4 normalRough;
    float flags;
    bool reflective;
};

// first >= 0 (reflections.ray_budget=quarter): the 2x2's reflective pixel at or after index
// `first` in the order 0, 1, 2, 3 (cyclic) instead, so that as `first` rotates frame by frame each
// reflective pixel of the block is chosen at least once every four frames.
GuideChoice chooseGuidePixel(ivec2 halfPixel, int first) {
    ivec2 fullSize = ivec2(rf.size.xy);
    bool closest = ((halfPixel.x + halfPixel.y) & 1) == 0;
    GuideChoice best;
    best.index = 0;
    best.depth = -1.0;
    best.reflective = false;
    // A straight loop body over the four (lavapipe runs every branch for all lanes anyway).
    for (int i = 0; i < 4; ++i) {
        ivec2 p = min(halfPixel * 2 + ivec2(i & 1, i >> 1), fullSize - 1);
        float depth = texelFetch(hiz, p, 0).g;
        vec4 normalRough = texelFetch(normalTex, p, 0);
        float flags = texelFetch(emissiveTex, p, 0).a;
        bool reflective = pixelMaterial(flags, normalRough.w).reflective && depth > 0.0;
        // The rotation's distance from `first`: smaller is preferred among reflective pixels.
        int after = (i - first) & 3, bestAfter = (best.index - first) & 3;
        bool order = first >= 0 ? after < bestAfter
                                : (closest ? depth > best.depth : depth < best.depth);
        bool better = best.depth < 0.0 || (reflective && !best.reflective) || (reflective == best.reflective && order);
        if (better) {
            best.index = i;
            best.pixel = p;
            best.depth = depth;
            best.normalRough = normalRough;
            best.flags = flags;
            best.reflective = reflective;
        }
    }
    return best;
}
#endif

#endif
