#version 460
#extension GL_GOOGLE_include_directive : require
// render.depth_prepass: the same clip position as gbuffer.vert, bit for bit (the same
// expression, both precise), so that render.gbuffer can test against this depth without writing it.
#include "engine/gbuffer_common.glsl"

layout(location = 0) in vec3 inPosition;
// Declared so that the engine's vertex layout matches the shader interface exactly.
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec4 inTangent;
layout(location = 3) in vec2 inUV;

precise gl_Position;  // see gbuffer.vert

void main() {
    vec4 world = draw.model * vec4(inPosition, 1.0);
    gl_Position = frame.viewProj * world;
}
