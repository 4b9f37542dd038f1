#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.hit_reuse with CMOs: the screen-space hits, then the CMOs' (hit_reuse.glsl).
#define HIT_REUSE_CMOS
#include "reflections/shaders/hit_reuse.glsl"
