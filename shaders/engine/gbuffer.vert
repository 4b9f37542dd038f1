#version 460
#extension GL_GOOGLE_include_directive : require
#include "engine/gbuffer_common.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec4 inTangent;
layout(location = 3) in vec2 inUV;

layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec4 outTangent;
layout(location = 2) out vec2 outUV;
layout(location = 3) out vec4 outClip;
layout(location = 4) out vec4 outPrevClip;

// Must match depth_prepass.vert bit for bit: render.gbuffer tests against the prepass's depth.
// `precise` (no FMA contraction or reassociation) rather than `invariant`: glslang puts
// Invariant on the gl_PerVertex member, which the validation layer's SPIR-V validator rejects.
precise gl_Position;

void main() {
    vec4 world = draw.model * vec4(inPosition, 1.0);
    mat3 m = mat3(draw.model);
    // Cofactor matrix: the inverse transpose up to a scale (normalized later), without an
    // inverse per vertex. Its sign follows the determinant, hence the correction.
    mat3 cof = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
    float det = dot(m[0], cof[0]);
    outNormal = cof * inNormal * sign(det);
    outTangent = vec4(m * inTangent.xyz, inTangent.w);
    outUV = inUV;
    outClip = frame.viewProj * world;
    // Scenes are static: only the camera moves between frames.
    outPrevClip = frame.prevViewProj * world;
    gl_Position = outClip;
}
