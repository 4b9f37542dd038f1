#version 460
// The viewport's image scaled into its rectangle of the window (editor.ui), drawn in the render
// pass of ImGui's overlays: on lavapipe a pass costs by its area, and a blit of its own over the
// same 660x511 rectangle cost as much again (about 3 ms).
layout(set = 0, binding = 0) uniform sampler2D image;  // linear, clamped

layout(push_constant) uniform Push {
    vec4 rect;  // x, y, width, height in window pixels
} pc;

layout(location = 0) out vec4 color;

void main() {
    color = textureLod(image, (gl_FragCoord.xy - pc.rect.xy) / pc.rect.zw, 0.0);
}
