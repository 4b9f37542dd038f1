#version 460
#extension GL_GOOGLE_include_directive : require
// render.gbuffer for materials with at least one texture (see gbuffer_frag.glsl).
#include "engine/gbuffer_frag.glsl"
