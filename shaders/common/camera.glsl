// View conventions (renderer.hpp): reversed-Z with an infinite far plane (depth 1 at the near
// plane, 0 at infinity), Vulkan clip space with y down, pixel (x, y) centred at
// ((x + 0.5) / w, (y + 0.5) / h) in UV. primaryRay() in engine/render/camera.cpp is the CPU twin.
#ifndef SPECULUM_CAMERA_GLSL
#define SPECULUM_CAMERA_GLSL

vec2 pixelCenterUV(ivec2 pixel, ivec2 size) {
    return (vec2(pixel) + 0.5) / vec2(size);
}

vec2 uvToNdc(vec2 uv) {
    return uv * 2.0 - 1.0;
}

vec2 ndcToUV(vec2 ndc) {
    return ndc * 0.5 + 0.5;
}

// World position of a depth-buffer sample. Depth 0 (infinity) has no finite position.
vec3 worldFromDepth(vec2 uv, float depth, mat4 invViewProj) {
    vec4 p = invViewProj * vec4(uvToNdc(uv), depth, 1.0);
    return p.xyz / p.w;
}

// Unit direction from the eye through uv, from two points on the ray, so that perspective and
// orthographic projections both work (the same construction as primaryRay on the CPU).
vec3 viewRayDirection(vec2 uv, mat4 invViewProj) {
    vec3 nearPoint = worldFromDepth(uv, 1.0, invViewProj);
    vec3 farPoint = worldFromDepth(uv, 0.5, invViewProj);
    return normalize(farPoint - nearPoint);
}

// UV a world position projects to (for reprojection and motion vectors).
vec2 projectToUV(vec3 world, mat4 viewProj) {
    vec4 clip = viewProj * vec4(world, 1.0);
    return ndcToUV(clip.xy / clip.w);
}

#endif
