// The tile lists of reflections.classify, declared once for C++ (modules/reflections/passes.cpp
// sizes, clears and dispatches them) and GLSL (tiles.glsl reads them). Work follows need (issue
// 23): each 8x8 tile of the trace's resolution is classified by what its pixels need, and each
// per-pixel pass runs by indirect dispatch: its full shader (or a variant without what the
// tile's pixels do not need) on the tiles of its work lists, and on the rest either nothing (its
// outputs cleared beforehand to what the full shader writes for a pixel that needs nothing) or
// a fill variant that writes those values. A pixel's result is then the same as without tiles;
// only whole tiles skip the work none of their pixels needs.
//
// The buffer: kTileLists VkDispatchIndirectCommand headers (x: the list's tile count, y = z = 1,
// 16 bytes apart), then the entries interleaved, entry i of list k at entries[i * kTileLists + k]
// (so that no list needs the screen's tile count to find its start), each a tile packed as
// x | y << 16.
#ifndef SPECULUM_REFLECTIONS_TILES_H
#define SPECULUM_REFLECTIONS_TILES_H

#include "common/host_device.h"

SPECULUM_SHADER_NAMESPACE_BEGIN(speculum::reflections::shader)

SPECULUM_CONSTANT(uint, kTileSize, 8u);  // the passes' workgroup size: one workgroup per tile
SPECULUM_CONSTANT(uint, kTileLists, 10u);
// The lists. A tile is in at most one of each pass's lists: the trace and the CMO trace have a
// work list only (the rest of their outputs is a transfer's clear: on lavapipe the fill variants
// that wrote the same constants cost 1.6-3.7 ms at 960x540, a clear about 1), the resolve has a
// fill list too (a tile that reflects nothing is rare, and its outputs are three images).
SPECULUM_CONSTANT(uint, kListTrace, 0u);       // some pixel traces a screen-space ray
SPECULUM_CONSTANT(uint, kListCmo, 1u);         // some pixel may trace the CMOs
SPECULUM_CONSTANT(uint, kListResolveRay, 2u);  // some pixel resolves a screen-space ray (= kListTrace)
SPECULUM_CONSTANT(uint, kListLookup, 3u);      // reflective pixels, none with a ray: probes, CMOs, sky only
SPECULUM_CONSTANT(uint, kListResolveFill, 4u); // nothing reflects
// The resolve's own split of the two lists above (the other full-size passes take them whole):
// what its pixels' lobes need, so that a tile compiles out what none of its pixels runs
// (lavapipe runs both sides of every branch; on a GPU a coherent wave skips them anyway).
SPECULUM_CONSTANT(uint, kListResolveMirror, 5u);  // kListResolveRay, every ray a mirror's (no cone)
SPECULUM_CONSTANT(uint, kListResolveCone, 6u);    // kListResolveRay, some ray with a cone
SPECULUM_CONSTANT(uint, kListLookupRough, 7u);    // kListLookup, every lobe rough (kNarrowLobeMaxRoughness and up)
SPECULUM_CONSTANT(uint, kListLookupNarrow, 8u);   // kListLookup, some lobe narrower
// Not a list: entries[t * kTileLists + kListArrivals] is tile t's (row-major index) word that
// reflections.classify gathers its subgroups' needs in (zeroed by reflections.tile_clear): the
// first three needs in 3 bits per subgroup (bits 0-23), the subgroups arrived counted from bit
// kArrivalCountShift (4 bits), and kNeedCone and kNeedNarrow shifted by kArrivalRareShift.
SPECULUM_CONSTANT(uint, kListArrivals, 9u);
SPECULUM_CONSTANT(uint, kArrivalCountShift, 24u);
SPECULUM_CONSTANT(uint, kArrivalRareShift, 25u);  // kNeedCone (8) at bit 28, kNeedNarrow (16) at 29
// A pixel's needs (reflections.classify says what each means; the tiles debug view shows them).
SPECULUM_CONSTANT(uint, kNeedRay, 1u);
SPECULUM_CONSTANT(uint, kNeedCmo, 2u);
SPECULUM_CONSTANT(uint, kNeedResolve, 4u);
SPECULUM_CONSTANT(uint, kNeedCone, 8u);
SPECULUM_CONSTANT(uint, kNeedNarrow, 16u);

// How a per-pixel pass's pipeline is dispatched (its specialization constant kTileMode, id 310).
SPECULUM_CONSTANT(uint, kTileModeScreen, 0u);  // over the whole screen (reflections.tiles off)
SPECULUM_CONSTANT(uint, kTileModeWork, 1u);    // the pass's work list: the full shader
SPECULUM_CONSTANT(uint, kTileModeFill, 2u);    // the resolve's fill list: outputs of a pixel that needs nothing
SPECULUM_CONSTANT(uint, kTileModeLookup, 3u);  // the resolve on kListLookupNarrow: no screen-space term
SPECULUM_CONSTANT(uint, kTileModeMirror, 4u);  // the resolve on kListResolveMirror: no cone loop
SPECULUM_CONSTANT(uint, kTileModeRough, 5u);   // the resolve on kListLookupRough: no narrow-lobe steps

SPECULUM_SHADER_NAMESPACE_END

#endif
