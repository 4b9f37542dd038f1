// The joint bilateral upsampler's push constants, declared once for C++
// (modules/reflections/upsample.cpp fills them) and GLSL (shaders/reflections/upsample.comp).
// std430 push-constant layout: the matrix, then two 16-byte rows.
#ifndef SPECULUM_REFLECTIONS_UPSAMPLE_H
#define SPECULUM_REFLECTIONS_UPSAMPLE_H

#ifdef __cplusplus
#include <glm/glm.hpp>
namespace speculum::reflections::shader {
using mat4 = glm::mat4;
using vec4 = glm::vec4;
#define SPECULUM_UPSAMPLE_BEGIN struct UpsampleParams
#define SPECULUM_UPSAMPLE_END
#else
#define SPECULUM_UPSAMPLE_BEGIN layout(push_constant, std430) uniform UpsampleParams
#define SPECULUM_UPSAMPLE_END up
#endif

SPECULUM_UPSAMPLE_BEGIN {
    mat4 invViewProj;  // full-resolution uv and reversed-Z depth to world
    vec4 size;         // full width, height; low-resolution width, height
    vec4 eye;          // xyz camera position, w unused
} SPECULUM_UPSAMPLE_END;

#ifdef __cplusplus
}  // namespace speculum::reflections::shader
#endif

#endif
