// Node hierarchy: parsing with cycle checks, world transforms, and the flattened view the
// renderer draws (instances, lights and cameras in world space, scene bounds).
#define GLM_ENABLE_EXPERIMENTAL
#include "gltf_document.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/gtx/matrix_decompose.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace speculum::gltf {

namespace {

void parseTransform(Node& n, const json& j, const std::string& where, const Reader& r) {
    auto t = r.floats(j, "translation", where, 3, {0, 0, 0});
    auto q = r.floats(j, "rotation", where, 4, {0, 0, 0, 1});
    auto s = r.floats(j, "scale", where, 3, {1, 1, 1});
    n.translation = {t[0], t[1], t[2]};
    // glTF stores quaternions as x, y, z, w; glm's constructor takes w first.
    glm::quat rot(q[3], q[0], q[1], q[2]);
    float len = glm::length(rot);
    if (!(len > 1e-6f)) r.fail(where + ".rotation", "not a unit quaternion (length 0)");
    n.rotation = rot / len;
    n.scale = {s[0], s[1], s[2]};
    if (j.contains("matrix")) {
        auto m = r.floats(j, "matrix", where, 16, {});
        n.matrix = glm::make_mat4(m.data());  // both glTF and glm are column-major
        glm::vec3 skew;
        glm::vec4 perspective;
        glm::vec3 scale, translation;
        glm::quat rotation;
        if (glm::decompose(*n.matrix, scale, rotation, translation, skew, perspective)) {
            n.translation = translation;
            n.rotation = glm::normalize(rotation);
            n.scale = scale;
        }
    }
}

void parseNodeExtensions(Node& n, const json& j, const std::string& where, const Document& d,
                         const Reader& r) {
    const json* exts = r.object(j, "extensions", where);
    if (!exts) return;
    std::string ew = where + ".extensions";
    if (const json* l = r.object(*exts, "KHR_lights_punctual", ew))
        n.light = r.index(*l, "light", ew + ".KHR_lights_punctual", d.lights.size(),
                          "KHR_lights_punctual lights", true);
    if (const json* p = r.object(*exts, kProbeExt, ew))
        n.probe = parseProbe(*p, ew + "." + kProbeExt, r);
}

// glTF nodes must form strict trees: one parent each, nobody their own ancestor.
void linkAndCheckCycles(Scene& scene, const json& nodes, const Reader& r) {
    const size_t count = scene.nodes.size();
    for (size_t i = 0; i < count; ++i) {
        for (int c : scene.nodes[i].children) {
            std::string where = elementName("nodes", i, nodes[i]) + ".children";
            if (size_t(c) == i) r.fail(where, "the node is its own child (recursive nodes)");
            Node& child = scene.nodes[c];
            if (child.parent >= 0)
                r.fail(where, "node " + std::to_string(c) + " already has parent node " +
                                  std::to_string(child.parent) +
                                  " (a node may have only one parent)");
            child.parent = int(i);
        }
    }
    std::vector<uint8_t> state(count, 0);  // 0 unseen, 1 on the current walk, 2 known acyclic
    std::vector<int> path;
    for (size_t i = 0; i < count; ++i) {
        path.clear();
        int j = int(i);
        while (j >= 0 && state[j] == 0) {
            state[j] = 1;
            path.push_back(j);
            j = scene.nodes[j].parent;
        }
        if (j >= 0 && state[j] == 1)
            r.fail(elementName("nodes", size_t(j), nodes[j]),
                   "recursive nodes: the node is its own ancestor (cycle in children)");
        for (int k : path) state[k] = 2;
    }
}

// A camera-to-world matrix must be rigid, or view matrices shear; node scale is dropped.
glm::mat4 rigid(const glm::mat4& m) {
    glm::mat4 out = m;
    for (int c = 0; c < 3; ++c) {
        float len = glm::length(glm::vec3(m[c]));
        if (!(len > 1e-12f)) return glm::translate(glm::mat4(1.0f), glm::vec3(m[3]));
        out[c] = glm::vec4(glm::vec3(m[c]) / len, 0.0f);
    }
    return out;
}

void place(Scene& scene, int nodeIndex, const Document& d) {
    const Node& n = scene.nodes[nodeIndex];
    if (n.mesh >= 0) scene.instances.push_back({nodeIndex, n.mesh, n.world});
    if (n.light >= 0) {
        Light l = d.lights[n.light];
        if (!n.name.empty()) l.name = n.name;
        l.position = glm::vec3(n.world[3]);
        glm::vec3 dir = glm::mat3(n.world) * glm::vec3(0, 0, -1);
        float len = glm::length(dir);
        l.direction = len > 1e-12f ? dir / len : glm::vec3(0, 0, -1);
        scene.lights.push_back(l);
    }
    if (n.camera >= 0) {
        Camera c = d.cameras[n.camera];
        if (!n.name.empty()) c.name = n.name;
        c.world = rigid(n.world);
        scene.cameras.push_back(c);
    }
}

void computeBounds(Scene& scene) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    bool any = false;
    for (const Instance& inst : scene.instances) {
        for (const Primitive& p : scene.meshes[inst.mesh].primitives) {
            if (p.vertices.empty()) continue;
            for (int corner = 0; corner < 8; ++corner) {
                glm::vec3 c((corner & 1) ? p.boundsMax.x : p.boundsMin.x,
                            (corner & 2) ? p.boundsMax.y : p.boundsMin.y,
                            (corner & 4) ? p.boundsMax.z : p.boundsMin.z);
                glm::vec3 w = glm::vec3(inst.world * glm::vec4(c, 1.0f));
                lo = glm::min(lo, w);
                hi = glm::max(hi, w);
                any = true;
            }
        }
    }
    scene.boundsMin = any ? lo : glm::vec3(0.0f);
    scene.boundsMax = any ? hi : glm::vec3(0.0f);
}

}  // namespace

void parseNodes(Scene& scene, const json& doc, const Document& d, const Reader& r) {
    const json& nodes = r.topArray(doc, "nodes");
    const size_t count = nodes.size();
    scene.nodes.resize(count);
    for (size_t i = 0; i < count; ++i) {
        const json& j = nodes[i];
        std::string where = elementName("nodes", i, j);
        Node& n = scene.nodes[i];
        n.name = r.string(j, "name", where);
        n.mesh = r.index(j, "mesh", where, d.meshes.size(), "meshes");
        n.camera = r.index(j, "camera", where, d.cameras.size(), "cameras");
        // glTF lets extras be any JSON value; only an object can carry the flag.
        if (auto extras = j.find("extras");
            extras != j.end() && extras->is_object() && extras->contains("speculum_hidden_primary")) {
            const json& h = (*extras)["speculum_hidden_primary"];
            if (!h.is_boolean())
                r.fail(where + ".extras.speculum_hidden_primary", std::string("expected a boolean, got ") + jsonTypeName(h));
            n.hiddenPrimary = h.get<bool>();
        }
        if (const json* children = r.array(j, "children", where)) {
            for (size_t k = 0; k < children->size(); ++k) {
                std::string cw = where + ".children[" + std::to_string(k) + "]";
                const json& c = (*children)[k];
                if (!c.is_number_integer())
                    r.fail(cw, std::string("expected an integer, got ") + jsonTypeName(c));
                int64_t v = c.get<int64_t>();
                if (v < 0 || uint64_t(v) >= count)
                    r.fail(cw, "index " + std::to_string(v) + " out of range (the file has " +
                                   std::to_string(count) + " nodes)");
                n.children.push_back(int(v));
            }
        }
        parseTransform(n, j, where, r);
        parseNodeExtensions(n, j, where, d, r);
    }
    linkAndCheckCycles(scene, nodes, r);

    if (d.sceneIndex >= 0) {
        const json& s = doc["scenes"][d.sceneIndex];
        for (const json& v : s["nodes"]) {
            int root = v.get<int>();
            if (scene.nodes[root].parent >= 0)
                r.fail(elementName("scenes", d.sceneIndex, s),
                       "root node " + std::to_string(root) + " is a child of another node");
            if (std::find(scene.roots.begin(), scene.roots.end(), root) == scene.roots.end())
                scene.roots.push_back(root);
        }
    } else {
        for (size_t i = 0; i < count; ++i)
            if (scene.nodes[i].parent < 0) scene.roots.push_back(int(i));
    }
}

void resolveScene(Scene& scene, const json& /*doc*/, const Document& d, const Reader& /*r*/) {
    // Every tree gets world matrices (the editor shows nodes outside the active scene too).
    std::vector<int> stack;
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].parent < 0) stack.push_back(int(i));
    while (!stack.empty()) {
        int i = stack.back();
        stack.pop_back();
        Node& n = scene.nodes[i];
        glm::mat4 parentWorld = n.parent >= 0 ? scene.nodes[n.parent].world : glm::mat4(1.0f);
        n.world = parentWorld * localMatrix(n);
        for (int c : n.children) stack.push_back(c);
    }
    // Only the active scene is drawn; depth-first in file order keeps instance order stable.
    for (auto it = scene.roots.rbegin(); it != scene.roots.rend(); ++it) stack.push_back(*it);
    while (!stack.empty()) {
        int i = stack.back();
        stack.pop_back();
        place(scene, i, d);
        const auto& ch = scene.nodes[i].children;
        for (auto it = ch.rbegin(); it != ch.rend(); ++it) stack.push_back(*it);
    }
    computeBounds(scene);
}

}  // namespace speculum::gltf

namespace speculum {

glm::mat4 localMatrix(const Node& n) {
    if (n.matrix) return *n.matrix;
    glm::mat4 m = glm::mat4_cast(n.rotation);
    m[0] *= n.scale.x;
    m[1] *= n.scale.y;
    m[2] *= n.scale.z;
    m[3] = glm::vec4(n.translation, 1.0f);
    return m;
}

std::vector<int> activeProbeNodes(const Scene& scene, ProbeKind kind) {
    // The active scene's trees, depth first from its roots (a cycle or a bad index is refused at
    // load; the editor keeps both valid), then file order, as the loader places meshes.
    std::vector<char> active(scene.nodes.size(), 0);
    std::vector<int> stack(scene.roots.rbegin(), scene.roots.rend());
    while (!stack.empty()) {
        int i = stack.back();
        stack.pop_back();
        if (i < 0 || size_t(i) >= scene.nodes.size() || active[size_t(i)]) continue;
        active[size_t(i)] = 1;
        for (int c : scene.nodes[size_t(i)].children) stack.push_back(c);
    }
    std::vector<int> out;
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (active[i] && scene.nodes[i].probe && scene.nodes[i].probe->kind == kind) out.push_back(int(i));
    return out;
}

}  // namespace speculum
