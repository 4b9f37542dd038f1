// Tangent generation for primitives without TANGENT, close to what MikkTSpace gives for
// typical meshes (so normal maps baked by Blender/Substance look right):
//  - per triangle, tangent T and bitangent B from the UV derivatives, computed with V flipped.
//    glTF's V runs down the image while normal maps' green axis points up the image, and
//    MikkTSpace (as run by exporters) works in that V-up frame;
//  - T and B are normalised per triangle and accumulated per vertex weighted by the corner
//    angle, as MikkTSpace does, so triangle size and tessellation do not bias the result;
//  - per vertex, T is Gram-Schmidt orthogonalised against the normal, and the handedness
//    w = sign(dot(cross(N, T), B)), so the shader's bitangent is cross(N, T) * w (glTF rule).
// Differences from MikkTSpace: vertices are not split where mirrored UV islands share a vertex
// (the file's vertex sharing is kept), and degenerate UVs fall back to any T perpendicular to N.
#include "gltf_document.hpp"

#include <cmath>

namespace speculum::gltf {

namespace {

glm::vec3 anyPerpendicular(const glm::vec3& n) {
    glm::vec3 axis = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(n, axis));
}

float cornerAngle(const glm::vec3& at, const glm::vec3& a, const glm::vec3& b) {
    glm::vec3 u = a - at, v = b - at;
    float lu = glm::length(u), lv = glm::length(v);
    if (!(lu > 0.0f) || !(lv > 0.0f)) return 0.0f;
    return std::acos(glm::clamp(glm::dot(u, v) / (lu * lv), -1.0f, 1.0f));
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

void generateTangents(Primitive& p) {
    const size_t n = p.vertices.size();
    std::vector<glm::vec3> tan(n, glm::vec3(0.0f)), bit(n, glm::vec3(0.0f));
    for (size_t t = 0; t + 2 < p.indices.size(); t += 3) {
        const uint32_t idx[3] = {p.indices[t], p.indices[t + 1], p.indices[t + 2]};
        const Vertex& v0 = p.vertices[idx[0]];
        const Vertex& v1 = p.vertices[idx[1]];
        const Vertex& v2 = p.vertices[idx[2]];
        glm::vec3 e1 = v1.position - v0.position, e2 = v2.position - v0.position;
        float du1 = v1.uv.x - v0.uv.x, du2 = v2.uv.x - v0.uv.x;
        float dv1 = -(v1.uv.y - v0.uv.y), dv2 = -(v2.uv.y - v0.uv.y);  // V flipped: V-up frame
        float det = du1 * dv2 - du2 * dv1;
        if (!(std::fabs(det) > 1e-20f)) continue;
        glm::vec3 T = (e1 * dv2 - e2 * dv1) / det;
        glm::vec3 B = (e2 * du1 - e1 * du2) / det;
        float lt = glm::length(T), lb = glm::length(B);
        if (!(lt > 0.0f) || !(lb > 0.0f) || !std::isfinite(lt) || !std::isfinite(lb)) continue;
        T /= lt;
        B /= lb;
        const glm::vec3* pos[3] = {&v0.position, &v1.position, &v2.position};
        for (int k = 0; k < 3; ++k) {
            float w = cornerAngle(*pos[k], *pos[(k + 1) % 3], *pos[(k + 2) % 3]);
            tan[idx[k]] += T * w;
            bit[idx[k]] += B * w;
        }
    }
    for (size_t i = 0; i < n; ++i) {
        Vertex& v = p.vertices[i];
        glm::vec3 t = tan[i] - v.normal * glm::dot(v.normal, tan[i]);
        float len = glm::length(t);
        t = len > 1e-12f && finite(t) ? t / len : anyPerpendicular(v.normal);
        float w = glm::dot(glm::cross(v.normal, t), bit[i]) < 0.0f ? -1.0f : 1.0f;
        v.tangent = glm::vec4(t, w);
    }
}

}  // namespace speculum::gltf
