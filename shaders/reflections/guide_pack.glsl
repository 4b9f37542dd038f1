// The guide's fourth channel (reflections/guide.comp writes it, reflections/upsample.comp and
// guidePixel() of common.glsl read it): w = +-(1 + bits), positive when the pixel reflects, with
// bits = index in the 2x2 (2 bits) | G-buffer roughness (6 bits) << 2 | octahedral normal
// (7 + 7 bits) << 8: 22 bits, so that the float holds them exactly (24-bit mantissa). The
// upsampler then reads each sample's normal and roughness with its position in one fetch
// instead of two (16 -> 12 fetches per full-resolution pixel). 7-bit octahedral normals are
// within about 1.5 degrees, which moves dot(n, n_sample)^32 by about 1%.
#ifndef SPECULUM_REFLECTIONS_GUIDE_PACK_GLSL
#define SPECULUM_REFLECTIONS_GUIDE_PACK_GLSL

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

#endif
