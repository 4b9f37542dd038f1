// A local cubemap probe's record as the shaders see it, declared once for C++ (modules/probes
// writes them: probes::shader::Probe, ProbeInfo::gpu) and GLSL (probes.glsl reads them from
// ProbeBuffer), std430: a matrix and three vec4 rows, 112 bytes.
#ifndef SPECULUM_PROBE_H
#define SPECULUM_PROBE_H

#include "common/host_device.h"

SPECULUM_SHADER_NAMESPACE_BEGIN(speculum::probes::shader)

struct Probe {
    mat4 worldToLocal;  // the probe node's inverse world transform: its shapes live in node space
    vec4 center;        // xyz capture point (world), w shape (0 box, 1 sphere)
    vec4 extents;       // xyz half-extents in node space (sphere: radius in x), w blend distance
    vec4 params;        // x cube index in the array, y the array's last mip, zw unused
};

#ifdef __cplusplus
static_assert(sizeof(Probe) == 112);
#endif
SPECULUM_SHADER_NAMESPACE_END

#endif
