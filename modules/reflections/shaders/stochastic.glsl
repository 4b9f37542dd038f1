// reflections.glossy = stochastic: one GGX visible-normal sample per traced pixel (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals"), shared by the trace (which traces it) and
// the resolve (which recomputes its neighbours' samples to weigh their hits, so nothing but the
// hit is stored). The noise is interleaved gradient noise (Jimenez 2014), a low-discrepancy
// pattern whose spectrum is blue-ish, moved every frame by the R2 sequence's step so that the
// temporal pass averages a new set: no blue-noise texture asset is needed.
// Include after common.glsl and common/brdf.glsl.
#ifndef SPECULUM_REFLECTIONS_STOCHASTIC_GLSL
#define SPECULUM_REFLECTIONS_STOCHASTIC_GLSL

float interleavedGradientNoise(vec2 p) {
    return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715))));
}

vec2 sampleNoise(ivec2 pixel, uint frame) {
    vec2 p = vec2(pixel) + 0.5;
    float f = float(frame % 1024u);
    // R2 (Roberts 2018) offsets per frame for each dimension.
    return vec2(fract(interleavedGradientNoise(p) + f * 0.7548776662),
                fract(interleavedGradientNoise(p + vec2(47.0, 17.0)) + f * 0.5698402910));
}

// An orthonormal basis around n (Duff et al. 2017).
void basis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// A half vector from GGX's visible normals for the direction to the eye `toEye` (unit, world).
vec3 sampleVisibleNormal(vec3 n, vec3 toEye, float alpha, vec2 u) {
    vec3 t, b;
    basis(n, t, b);
    vec3 ve = vec3(dot(toEye, t), dot(toEye, b), dot(toEye, n));
    vec3 vh = normalize(vec3(alpha * ve.x, alpha * ve.y, max(ve.z, 1e-4)));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u.x), phi = 6.28318530718 * u.y;
    float p1 = r * cos(phi), p2 = r * sin(phi);
    float s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    vec3 h = normalize(vec3(alpha * nh.x, alpha * nh.y, max(nh.z, 1e-6)));
    return normalize(h.x * t + h.y * b + h.z * n);
}

// Below this roughness the mirror direction is the sample (the lobe is narrower than a pixel's
// footprint, and the cone resolve is exact there).
const float kStochasticMinRoughness = 0.05;

// The reflected direction traced from a pixel: the mirror's, or the sample's. `view` is from the
// eye to the point.
vec3 stochasticDirection(ivec2 fullPixel, vec3 view, vec3 n, float roughness) {
    vec3 mirror = reflect(view, n);
    if (roughness < kStochasticMinRoughness) return mirror;
    vec3 h = sampleVisibleNormal(n, -view, roughnessToAlpha(roughness), sampleNoise(fullPixel, rf.frameIndex));
    vec3 l = reflect(view, h);
    return dot(l, n) > 1e-3 ? l : mirror;
}

// The visible-normal pdf of direction l (per solid angle): G1(v) D(h) / (4 n.v).
float visibleNormalPdf(vec3 n, vec3 toEye, vec3 l, float alpha) {
    vec3 h = normalize(toEye + l);
    float NoV = max(dot(n, toEye), 1e-4);
    float a2 = alpha * alpha;
    float g1 = 2.0 * NoV / (NoV + sqrt(a2 + (1.0 - a2) * NoV * NoV));
    return g1 * D_GGX(max(dot(n, h), 0.0), alpha) / (4.0 * NoV);
}

#endif
