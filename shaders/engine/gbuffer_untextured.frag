#version 460
#extension GL_GOOGLE_include_directive : require
// render.gbuffer for materials whose textures are all 1x1 defaults (see gbuffer_frag.glsl).
#define GBUFFER_UNTEXTURED
#include "engine/gbuffer_frag.glsl"
