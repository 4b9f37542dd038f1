// Colour transforms for display.
#ifndef SPECULUM_COLOR_GLSL
#define SPECULUM_COLOR_GLSL

// sRGB opto-electronic transfer function (IEC 61966-2-1), linear [0,1] to encoded.
vec3 srgbEncode(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    vec3 lo = c * 12.92;
    vec3 hi = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(hi, lo, lessThanEqual(c, vec3(0.0031308)));
}

vec3 srgbDecode(vec3 encoded) {
    vec3 c = clamp(encoded, 0.0, 1.0);
    vec3 lo = c / 12.92;
    vec3 hi = pow((c + 0.055) / 1.055, vec3(2.4));
    return mix(hi, lo, lessThanEqual(c, vec3(0.04045)));
}

// Narkowicz's fit of the ACES filmic curve (2015), applied as is: exposure is the caller's
// (his 0.6 pre-scale is left to RendererOptions::exposure).
vec3 acesFitted(vec3 x) {
    const float a = 2.51;
    const float b = 0.03;
    const float c = 2.43;
    const float d = 0.59;
    const float e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

float luminance(vec3 linear) {
    return dot(linear, vec3(0.2126, 0.7152, 0.0722));
}

#endif
