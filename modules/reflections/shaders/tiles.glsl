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

// The full-resolution passes on the trace's tiles (reflections.reproject, reflections.composite):
// a tile's footprint is kTileSize * scale full pixels a side (scale 2 at half resolution), in
// scale x scale blocks of kTileSize; `i` is the block (composite: a workgroup each, the
// dispatch's y from reflections.footprint_args; reproject: one workgroup loops over them).
ivec2 footprintPixel(uint list, uint scale, uint i) {
    uint e = tiles.entries[gl_WorkGroupID.x * kTileLists + list];
    return ivec2(e & 0xffffu, e >> 16) * int(kTileSize * scale) + ivec2(gl_LocalInvocationID.xy) +
           ivec2(i % scale, i / scale) * int(kTileSize);
}

#endif
