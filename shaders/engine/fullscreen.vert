#version 460
// One triangle covering the viewport (vertices 0..2, no vertex input) for fullscreen fragment
// passes: lavapipe writes colour attachments through its tiled rasteriser, far cheaper than
// imageStore from compute.
void main() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
