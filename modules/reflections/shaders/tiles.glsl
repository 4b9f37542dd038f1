// Tile-list dispatch for the per-pixel passes (tiles.h has the layout and the lists). Define
// SPECULUM_TILES_WRITE before including it to write the lists (reflections.classify).
#ifndef SPECULUM_REFLECTIONS_TILES_GLSL
#define SPECULUM_REFLECTIONS_TILES_GLSL

#include "reflections/shaders/tiles.h"

layout(constant_id = 310) const uint kTileMode = 0u;

#ifdef SPECULUM_TILES_WRITE
layout(set = 0, binding = 18, std430) buffer TileList {
#else
layout(set = 0, binding = 18, std430) readonly buffer TileList {
#endif
    uvec4 args[kTileLists];  // xyz: VkDispatchIndirectCommand
    uint entries[];
} tiles;

// The pixel (at the pass's resolution) of this invocation: the global id over the whole screen,
// else the `list`'s tile of this workgroup. The list is a workgroup's own: tiles never overlap.
ivec2 tilePixel(uint list) {
    if (kTileMode == kTileModeScreen) return ivec2(gl_GlobalInvocationID.xy);
    uint e = tiles.entries[gl_WorkGroupID.x * kTileLists + list];
    return ivec2(e & 0xffffu, e >> 16) * int(kTileSize) + ivec2(gl_LocalInvocationID.xy);
}

// What a tile's pixels need (kNeed* bits) from its kListArrivals word as classify left it:
// three bits per subgroup (kNeedRay, kNeedCmo, kNeedResolve) in bits 0-23, and the rarer two
// (kNeedCone, kNeedNarrow) ORed in above the arrival count (tiles.h). Unused subgroups' bits
// are 0, so all eight fields are read.
uint tileNeeds(uint word) {
    uint needs = (word >> kArrivalRareShift) & (kNeedCone | kNeedNarrow);
    for (uint k = 0u; k < 8u; ++k) needs |= (word >> (3u * k)) & 7u;
    return needs;
}

// The full-resolution passes on the trace's tiles (reflections.reproject, reflections.composite):
// a tile's footprint is kTileSize * scale full pixels a side (scale 2 at half resolution), in
// scale x scale blocks of kTileSize, a workgroup each (reflections.footprint_args: x the list's
// count, y the scale x scale blocks). Workgroup (x, y) takes block linear % blocks of the tile
// linear / blocks, linear = y * count + x, so that the workgroups a driver runs one after
// another (x fastest) cover one footprint's blocks together. Block y of every tile in turn (the
// first version) read the images in 64-byte runs 128 bytes apart, against the prefetcher: on
// closed_room.main at half resolution the composite cost 16.8 ms that way against 12.2 over the
// whole screen, now 11.6 against 11.3 (MEASUREMENTS.md, issue 23, 2026-12-04).
ivec2 footprintBlockPixel(uint list, uint scale) {
    uint blocks = scale * scale;
    uint linear = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint e = tiles.entries[(linear / blocks) * kTileLists + list];
    uint i = linear % blocks;
    return ivec2(e & 0xffffu, e >> 16) * int(kTileSize * scale) + ivec2(gl_LocalInvocationID.xy) +
           ivec2(i % scale, i / scale) * int(kTileSize);
}

#endif
