// The joint bilateral upsampler's push constants, declared once for C++
// (modules/reflections/upsample.cpp fills them) and GLSL (modules/reflections/shaders/upsample.comp).
// std430 push-constant layout: the matrix, then two 16-byte rows.
#ifndef SPECULUM_REFLECTIONS_UPSAMPLE_H
#define SPECULUM_REFLECTIONS_UPSAMPLE_H

#include "common/host_device.h"

SPECULUM_SHADER_NAMESPACE_BEGIN(speculum::reflections::shader)

SPECULUM_BLOCK(layout(push_constant, std430) uniform, UpsampleParams) {
    mat4 invViewProj;  // full-resolution uv and reversed-Z depth to world
    vec4 size;         // full width, height; low-resolution width, height
    vec4 eye;          // xyz camera position, w unused
} SPECULUM_BLOCK_INSTANCE(up);

SPECULUM_SHADER_NAMESPACE_END

#endif
