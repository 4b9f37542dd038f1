#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.hit_reuse without CMOs: the screen-space hits alone (hit_reuse.glsl).
#include "reflections/shaders/hit_reuse.glsl"
