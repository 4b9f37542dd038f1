// A cubemap-tracing object (CMO, seed 000) as the shaders see it: declared once for C++
// (modules/probes, which writes the records) and GLSL (modules/probes/shaders/cmo.glsl, which traces
// them), std430. The CMO arrays (radiance, distance hierarchy, attributes) hold six layers per
// CMO; a CMO captured below the arrays' largest face size uses the mip whose size is its own
// as its level 0 (`baseMip`), so every CMO keeps its resolution in one set of arrays.
#ifndef SPECULUM_CMO_H
#define SPECULUM_CMO_H

#include "common/host_device.h"

SPECULUM_SHADER_NAMESPACE_BEGIN(speculum::probes::shader)

struct CmoRecord {
    vec4 center;  // xyz capture point (world), w face size of its level 0 in texels
    vec4 params;  // x first array layer (6 per CMO), y base mip in the arrays, z hierarchy levels
                  // (log2(size) + 1), w angle of one level-0 texel at a face's centre (2 / size, rad)
};

#ifdef __cplusplus
static_assert(sizeof(CmoRecord) == 32);
#endif
SPECULUM_SHADER_NAMESPACE_END

// The distance a CMO stores where it saw the sky: beyond every traced ray, so a min/max cell
// holding sky is skipped and a ray toward the sky never finds a crossing.
#define SPECULUM_CMO_SKY_DISTANCE 1.0e9

#endif
