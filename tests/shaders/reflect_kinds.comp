#version 460
// tests/unit/reflect_test.cpp: one binding of every kind the reflection reads (engine/gpu/reflect.cpp),
// an array, a named and an anonymous block, and a binding main() never reads.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform sampler2D textures[3];
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D target;
layout(set = 0, binding = 2, std140) uniform Params { vec4 scale; } params;
layout(set = 0, binding = 3, std430) readonly buffer Values { float values[]; };
layout(set = 0, binding = 5) uniform samplerCube unusedCube;  // declared, never read
void main() {
    vec4 c = texelFetch(textures[0], ivec2(0), 0) + texelFetch(textures[2], ivec2(0), 0);
    imageStore(target, ivec2(0), c * params.scale + values[0]);
}
