// Shading model shared by the engine's lighting, the reflections module and the ground-truth
// reference (which mirrors these formulas in C++): GGX normal distribution, height-correlated
// Smith visibility, Schlick Fresnel and Lambert diffuse, in glTF's metallic-roughness
// parameterisation. Every function is pure so that callers can evaluate lobes separately.
#ifndef SPECULUM_BRDF_GLSL
#define SPECULUM_BRDF_GLSL

#ifndef PI
#define PI 3.14159265358979323846
#endif

// Perceptual roughness 0 makes GGX a delta that punctual lights can never hit; this floor keeps
// highlights finite (and matches the reference renderer's clamp).
const float kMinRoughness = 0.045;
// Reflectance at normal incidence of dielectrics (IOR 1.5), as glTF specifies.
const vec3 kDielectricF0 = vec3(0.04);

float clampRoughness(float perceptualRoughness) {
    return clamp(perceptualRoughness, kMinRoughness, 1.0);
}

// alpha = perceptualRoughness^2 (glTF / Burley remapping).
float roughnessToAlpha(float perceptualRoughness) {
    float r = clampRoughness(perceptualRoughness);
    return r * r;
}

// GGX / Trowbridge-Reitz normal distribution D(h).
float D_GGX(float NoH, float alpha) {
    float a2 = alpha * alpha;
    float d = (NoH * a2 - NoH) * NoH + 1.0;
    return a2 / (PI * d * d);
}

// Height-correlated Smith visibility V = G / (4 NoL NoV) (Heitz 2014), so that
// specular = D * V * F without the 4 NoL NoV denominator.
float V_SmithGGXCorrelated(float NoV, float NoL, float alpha) {
    float a2 = alpha * alpha;
    float gv = NoL * sqrt(NoV * NoV * (1.0 - a2) + a2);
    float gl = NoV * sqrt(NoL * NoL * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-7);
}

vec3 F_Schlick(vec3 f0, float VoH) {
    // x^5 by multiplication: pow() is an exp2/log2 pair on CPU drivers.
    float x = 1.0 - VoH;
    float x2 = x * x;
    float f = x2 * x2 * x;
    return f0 + (vec3(1.0) - f0) * f;
}

float Fd_Lambert() {
    return 1.0 / PI;
}

// Base colour and metallic to the two lobes' colours.
vec3 diffuseColor(vec3 baseColor, float metallic) {
    return baseColor * (1.0 - metallic);
}
vec3 specularF0(vec3 baseColor, float metallic) {
    return mix(kDielectricF0, baseColor, metallic);
}

// The specular lobe D V F for light l (NoL > 0) seen from v. f0: specularF0(); alpha:
// roughnessToAlpha().
vec3 specularLobe(vec3 n, vec3 v, vec3 l, float NoL, vec3 f0, float alpha) {
    vec3 h = normalize(v + l);
    // Clamped so that grazing views (normal-mapped or interpolated normals facing away) stay
    // finite instead of producing NaN.
    float NoV = max(dot(n, v), 1e-4);
    float NoH = clamp(dot(n, h), 0.0, 1.0);
    float VoH = clamp(dot(v, h), 0.0, 1.0);
    vec3 F = F_Schlick(f0, VoH);
    return D_GGX(NoH, alpha) * V_SmithGGXCorrelated(NoV, NoL, alpha) * F;
}

// The specular lobe alone times cos(theta_l): what a surface's direct light adds that depends
// on the view (the Lambert lobe does not).
vec3 specularBRDFCos(vec3 n, vec3 v, vec3 l, vec3 f0, float alpha) {
    float NoL = dot(n, l);
    return NoL > 0.0 ? specularLobe(n, v, l, NoL, f0, alpha) * NoL : vec3(0.0);
}

// Full BRDF f(l, v) times cos(theta_l): multiply by the light's radiance (irradiance for
// punctual lights) to get outgoing radiance. n, v, l are unit vectors, v and l point away
// from the surface.
vec3 evalBRDFCos(vec3 n, vec3 v, vec3 l, vec3 baseColor, float metallic, float perceptualRoughness) {
    float NoL = dot(n, l);
    if (NoL <= 0.0) return vec3(0.0);
    vec3 specular = specularLobe(n, v, l, NoL, specularF0(baseColor, metallic), roughnessToAlpha(perceptualRoughness));
    vec3 diffuse = diffuseColor(baseColor, metallic) * Fd_Lambert();
    return (diffuse + specular) * NoL;
}

// tan(coneAngle(roughness)), coneAngle() of modules/reflections/math.cpp (the cone
// tracer's, the planar lookup's and the ground lookup's footprint), from its cosine:
// acos and tan cost a polynomial each per lane on a CPU driver.
float coneTan(float roughness) {
    float alpha = max(roughness * roughness, 1e-4);
    float power = 2.0 / (alpha * alpha) - 2.0;
    float c = exp2(log2(0.244) / (power + 1.0));
    return power > 1048576.0 ? 0.0 : sqrt(max(1.0 - c * c, 0.0)) / c;
}

#endif
