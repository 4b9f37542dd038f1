#version 460
// tests/hardening/driver_probe.cpp: a branch on a read-only storage-buffer value.
// Storage-buffer loads are never inlined: the reflections module's workaround (issue 15).
layout(local_size_x = 1) in;
layout(set = 0, binding = 0, std140) readonly buffer Params { uvec4 p; } params;
layout(set = 0, binding = 1, std430) writeonly buffer Out { float v[]; } outBuf;
void main() {
    float v = float(params.p.y);
    if (params.p.x == 1u) {
        v = v * 1.0001 + sin(v + 0.0) * cos(v * 1.0);
        v = v * 1.0001 + sin(v + 1.0) * cos(v * 2.0);
        v = v * 1.0001 + sin(v + 2.0) * cos(v * 3.0);
        v = v * 1.0001 + sin(v + 3.0) * cos(v * 4.0);
        v = v * 1.0001 + sin(v + 4.0) * cos(v * 5.0);
        v = v * 1.0001 + sin(v + 5.0) * cos(v * 6.0);
        v = v * 1.0001 + sin(v + 6.0) * cos(v * 7.0);
        v = v * 1.0001 + sin(v + 7.0) * cos(v * 8.0);
        v = v * 1.0001 + sin(v + 8.0) * cos(v * 9.0);
        v = v * 1.0001 + sin(v + 9.0) * cos(v * 10.0);
        v = v * 1.0001 + sin(v + 10.0) * cos(v * 11.0);
        v = v * 1.0001 + sin(v + 11.0) * cos(v * 12.0);
        v = v * 1.0001 + sin(v + 12.0) * cos(v * 13.0);
        v = v * 1.0001 + sin(v + 13.0) * cos(v * 14.0);
        v = v * 1.0001 + sin(v + 14.0) * cos(v * 15.0);
        v = v * 1.0001 + sin(v + 15.0) * cos(v * 16.0);
        v = v * 1.0001 + sin(v + 16.0) * cos(v * 17.0);
        v = v * 1.0001 + sin(v + 17.0) * cos(v * 18.0);
        v = v * 1.0001 + sin(v + 18.0) * cos(v * 19.0);
        v = v * 1.0001 + sin(v + 19.0) * cos(v * 20.0);
        v = v * 1.0001 + sin(v + 20.0) * cos(v * 21.0);
        v = v * 1.0001 + sin(v + 21.0) * cos(v * 22.0);
        v = v * 1.0001 + sin(v + 22.0) * cos(v * 23.0);
        v = v * 1.0001 + sin(v + 23.0) * cos(v * 24.0);
    }
    outBuf.v[0] = v;
}
