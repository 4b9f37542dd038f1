// L2 spherical harmonics (9 coefficients, RGB in xyz), real basis in the order
// (0,0) (1,-1) (1,0) (1,1) (2,-2) (2,-1) (2,0) (2,1) (2,2). The coefficients the engine stores
// are already convolved with the clamped cosine and divided by pi (see environment.hpp), so
// evaluating them at a normal gives the diffuse multiplier for albedo directly.
#ifndef SPECULUM_SH_GLSL
#define SPECULUM_SH_GLSL

vec3 evalSH9(vec4 sh[9], vec3 n) {
    vec3 r = sh[0].xyz * 0.282095;
    r += sh[1].xyz * (0.488603 * n.y);
    r += sh[2].xyz * (0.488603 * n.z);
    r += sh[3].xyz * (0.488603 * n.x);
    r += sh[4].xyz * (1.092548 * n.x * n.y);
    r += sh[5].xyz * (1.092548 * n.y * n.z);
    r += sh[6].xyz * (0.315392 * (3.0 * n.z * n.z - 1.0));
    r += sh[7].xyz * (1.092548 * n.x * n.z);
    r += sh[8].xyz * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(r, vec3(0.0));
}

#endif
