// Host/device glue: the one prologue that lets a header declare a struct once for C++ and GLSL
// (Falcor's HostDeviceShared.slangh is the model). A shared header includes this, then writes
//
//   SPECULUM_SHADER_NAMESPACE_BEGIN(speculum::reflections::shader)
//   SPECULUM_BLOCK(layout(set = 0, binding = 0, std140) readonly buffer, ReflectionFrame) {
//       mat4 viewProj;  // GLSL's type names; in C++ they are glm's
//       ...
//   } SPECULUM_BLOCK_INSTANCE(rf);
//   SPECULUM_SHADER_NAMESPACE_END
//
// In C++ the block is `struct ReflectionFrame` in that namespace (the layout qualifiers and the
// instance name vanish); in GLSL it is the qualified block with its instance name. A plain
// `struct` (an element of a buffer's array) needs no macro; SPECULUM_CONSTANT(uint, kName, 8u)
// declares a constant both sides read. The layouts agree only if the C++
// side follows the block's packing rules: the headers that include this static_assert their
// sizes and offsets.
#ifndef SPECULUM_HOST_DEVICE_H
#define SPECULUM_HOST_DEVICE_H

#ifdef __cplusplus
#include <glm/glm.hpp>

#include <cstdint>

namespace speculum::host_device {
using mat4 = glm::mat4;
using vec4 = glm::vec4;
using vec3 = glm::vec3;
using vec2 = glm::vec2;
using uvec4 = glm::uvec4;
using ivec4 = glm::ivec4;
using uint = uint32_t;
}  // namespace speculum::host_device

#define SPECULUM_SHADER_NAMESPACE_BEGIN(ns) \
    namespace ns {                          \
    using namespace ::speculum::host_device;
#define SPECULUM_SHADER_NAMESPACE_END }
#define SPECULUM_BLOCK(qualifiers, name) struct name
#define SPECULUM_BLOCK_INSTANCE(instance)
#define SPECULUM_CONSTANT(type, name, value) inline constexpr type name = value
#else
#define SPECULUM_SHADER_NAMESPACE_BEGIN(ns)
#define SPECULUM_SHADER_NAMESPACE_END
#define SPECULUM_BLOCK(qualifiers, name) qualifiers name
#define SPECULUM_BLOCK_INSTANCE(instance) instance
#define SPECULUM_CONSTANT(type, name, value) const type name = value
#endif

#endif
