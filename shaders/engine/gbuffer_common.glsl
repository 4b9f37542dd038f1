// Interface shared by gbuffer.vert, gbuffer.frag and shadow.vert (see engine/render/gbuffer.cpp).
#ifndef SPECULUM_GBUFFER_COMMON_GLSL
#define SPECULUM_GBUFFER_COMMON_GLSL

layout(set = 0, binding = 0) uniform FrameConstants {
    mat4 viewProj;
    mat4 prevViewProj;
} frame;

layout(push_constant) uniform DrawConstants {
    mat4 model;          // shadow pass: light viewProj * model
    vec4 baseColor;      // linear factor
    vec4 emissive;       // rgb emissive * strength, w material flags (kFlag*)
    vec4 params;         // x metallic, y roughness, z normal scale, w draw flags
} draw;

// Draw flags (params.w): how the instance is rasterized, not material data.
const uint kDrawDoubleSided = 1u;
// gl_FrontFacing means a glTF back face (pipeline winding convention or a mirroring transform).
const uint kDrawInvertFacing = 2u;

// Material flags (emissive.w), mirror renderer.hpp.
const uint kFlagUnlit = 1u;
const uint kFlagReflective = 2u;

#endif
