#version 460
// Depth-only shadow map for the first directional light: orthographic, reversed-Z (1 nearest
// the light), see engine/render/gbuffer.cpp.

layout(push_constant) uniform ShadowDraw {
    mat4 lightViewProjModel;
} draw;

layout(location = 0) in vec3 inPosition;
// Declared so that the engine's vertex layout matches the shader interface exactly.
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec4 inTangent;
layout(location = 3) in vec2 inUV;

void main() {
    gl_Position = draw.lightViewProjModel * vec4(inPosition, 1.0);
}
