// A local cubemap probe's record as the shaders see it, declared once for C++ (modules/probes
// writes them: probes::shader::Probe, ProbeInfo::gpu) and GLSL (probes.glsl reads them from
// ProbeBuffer), std430: a matrix and three vec4 rows, 112 bytes.
#ifndef SPECULUM_PROBE_H
#define SPECULUM_PROBE_H

#include "common/host_device.h"

SPECULUM_SHADER_NAMESPACE_BEGIN(speculum::probes::shader)

// The mirror band's top (perceptual roughness). A lobe narrower than this finds its hit on a
// local probe's captured distances (probes.glsl), and the planar probes' images and grounds serve
// it (planar.glsl's planarShare, ground.glsl's groundOverProbes, both zero from here up). Where
// every lobe is at least this rough none of those steps runs: reflections.classify sends such
// tiles to a resolve compiled without them. Every roughness scored the same with the march
// (cornell_mirrors, closed_room, gallery, plain_metals: rough bands within 0.03 dB), so wider
// lobes keep the proxy and its cost; the planar steps' limits are their own (their files).
SPECULUM_CONSTANT(float, kNarrowLobeMaxRoughness, 0.3f);

struct Probe {
    mat4 worldToLocal;  // the probe node's inverse world transform: its shapes live in node space
    vec4 center;        // xyz capture point (world), w shape (0 box, 1 sphere)
    vec4 extents;       // xyz half-extents in node space (sphere: radius in x), w blend distance
    vec4 params;        // x cube index in the array, y the array's last mip, z probes.distance_steps, w unused
};

// A planar probe's record (modules/probes/planar.cpp writes them each frame, planar.glsl reads
// them from PlanarBuffer), std430: two matrices and four vec4 rows, 192 bytes.
struct PlanarProbe {
    mat4 viewProj;      // the mirrored camera's: a point on the plane lands where the view sees it
    mat4 worldToPlane;  // world to the plane's frame (metres): x along the width, y the normal, z the depth
    vec4 plane;         // xyz unit normal (world), w = -dot(normal, origin): dot(plane.xyz, p) + w
    vec4 extents;       // x half width, y half depth (m), z cos of the normal tolerance, w distance tolerance (m)
    vec4 params;        // x layer of the image array, y its base mip, z rad per pixel at that mip, w last mip
    vec4 crop;          // the UV rectangle (min xy, max zw: texel centres) rendered this time; the rest is stale
};

// A planar probe's ground (planar.cpp renders it, probes.capture_bounce reads it from
// GroundBuffer): the plane inside its rectangle seen straight down, orthographically, with the
// renderer's own passes, so that a ray meeting the plane from above (a sphere's underside over a
// mirror floor) reads the floor it meets. A cube's proxy places that floor wrong wherever an
// object on the plane hides it from the capture point. std430: a matrix and two vec4 rows.
struct PlanarGround {
    mat4 viewProj;  // the orthographic camera's: the rectangle fills clip x and y in [-1, 1]
    vec4 plane;     // xyz unit normal (world), w = -dot(normal, origin)
    vec4 params;    // x layer of the ground array, y metres per texel (the longer side), z last mip, w 0
};

#ifdef __cplusplus
static_assert(sizeof(Probe) == 112);
static_assert(sizeof(PlanarGround) == 96);
static_assert(sizeof(PlanarProbe) == 192);
#endif
SPECULUM_SHADER_NAMESPACE_END

#endif
