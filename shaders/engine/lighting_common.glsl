// Scene-static lighting data, built once by engine/render/lighting.cpp: the lights' layout
// (lighting.frag takes them as specialization constants) and the shadow mask's uniform buffer
// (std140, all vec4 so std430 alike; mirrored there by GpuSceneShadow).
#ifndef SPECULUM_LIGHTING_COMMON_GLSL
#define SPECULUM_LIGHTING_COMMON_GLSL

const uint kMaxLights = 16u;
const uint kLightDirectional = 0u;
const uint kLightPoint = 1u;
const uint kLightSpot = 2u;

struct GpuLight {
    vec4 positionType;    // xyz world position, w type
    vec4 directionRange;  // xyz direction the light travels (unit), w range (0: infinite)
    vec4 radiance;        // rgb colour * intensity (lux or candela), w shadowed (1) or not
    vec4 cone;            // x angle scale, y angle offset (glTF spot falloff)
};

struct SceneShadow {
    mat4 shadowViewProj;  // world to the shadow map's clip space (orthographic, reversed-Z)
    vec4 shadowParams;    // x map size, y depth bias, z normal offset (world units), w enabled
    vec4 shadowToLight;   // xyz unit direction towards the shadowed light
};

#endif
