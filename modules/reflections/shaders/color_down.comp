#version 460
#extension GL_GOOGLE_include_directive : require
// reflections.color_pyramid: level N of the pre-convolved colour pyramid from level N - 1
// (Uludag 4.5.4): the normalized 7-tap Gaussian (0.001 0.028 0.233 0.474 0.233 0.028 0.001)
// centred on the coarse texel, whose centre falls between two fine texels, so each tap is the
// mean of two: 8 fine weights per axis. Separable through shared memory: 8x8 outputs need
// 22x22 fine texels. Alpha is the visibility pyramid's level N (see binding 3).
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D src;  // level N - 1
layout(set = 0, binding = 2, rgba16f) uniform writeonly image2D dst;
// Level N of the visibility pyramid, carried in alpha so that the resolve's cone samples get
// colour and visibility from one trilinear lookup (same sizes per level).
layout(set = 0, binding = 3) uniform sampler2D visibilityLevel;

const int kTile = 22;  // 2 * 8 + 6
const float kWeights[8] = float[8](0.0005, 0.0145, 0.1305, 0.3535, 0.3535, 0.1305, 0.0145, 0.0005);

shared vec3 fine[kTile][kTile];
shared vec3 rows[kTile][8];

void main() {
    ivec2 srcSize = textureSize(src, 0);
    ivec2 dstSize = imageSize(dst);
    ivec2 group = ivec2(gl_WorkGroupID.xy) * 8;
    ivec2 origin = group * 2 - 3;  // fine texel of tap 0 for the group's first output
    uint local = gl_LocalInvocationIndex;
    for (uint i = local; i < uint(kTile * kTile); i += 64u) {
        ivec2 t = ivec2(int(i) % kTile, int(i) / kTile);
        fine[t.y][t.x] = texelFetch(src, clamp(origin + t, ivec2(0), srcSize - 1), 0).rgb;
    }
    barrier();
    for (uint i = local; i < uint(kTile * 8); i += 64u) {
        int row = int(i) / 8;
        int col = int(i) % 8;
        vec3 sum = vec3(0.0);
        for (int k = 0; k < 8; ++k) sum += kWeights[k] * fine[row][col * 2 + k];
        rows[row][col] = sum;
    }
    barrier();
    ivec2 l = ivec2(gl_LocalInvocationID.xy);
    ivec2 cell = group + l;
    if (any(greaterThanEqual(cell, dstSize))) return;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 8; ++k) sum += kWeights[k] * rows[l.y * 2 + k][l.x];
    imageStore(dst, cell, vec4(sum, texelFetch(visibilityLevel, cell, 0).r));
}
