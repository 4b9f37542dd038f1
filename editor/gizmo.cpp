// The translate gizmo (three axes and the xz plane handle) and the probes' influence volumes,
// drawn with ImGui's background draw list over the viewport. The gizmo previews the drag and
// turns it into one move command when the mouse is released.
#include "app.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace speculum::editor {

namespace {

const ImU32 kAxisColors[3] = {IM_COL32(230, 70, 70, 255), IM_COL32(90, 210, 90, 255), IM_COL32(80, 130, 240, 255)};

float segmentDistance(ImVec2 p, ImVec2 a, ImVec2 b) {
    float dx = b.x - a.x, dy = b.y - a.y;
    float len2 = dx * dx + dy * dy;
    float t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0f, 1.0f) : 0.0f;
    float ex = a.x + t * dx - p.x, ey = a.y + t * dy - p.y;
    return std::sqrt(ex * ex + ey * ey);
}

glm::vec3 axisVector(int axis) {
    glm::vec3 v(0.0f);
    v[axis] = 1.0f;
    return v;
}

}  // namespace

bool EditorApp::project(const render::CameraState& cam, glm::vec3 world, float& x, float& y) const {
    glm::vec4 clip = cam.viewProj * glm::vec4(world, 1.0f);
    if (clip.w <= 1e-4f) return false;
    x = view_.x + (clip.x / clip.w * 0.5f + 0.5f) * view_.w;
    y = view_.y + (clip.y / clip.w * 0.5f + 0.5f) * view_.h;
    return true;
}

glm::vec3 EditorApp::handlePosition(const glm::mat4& world, const ReflectionProbe& probe, int handle) const {
    glm::vec3 local(0.0f);
    if (handle >= 4 && handle <= 6)
        local[handle - 4] = probe.shape == ProbeShape::Sphere ? probe.extents.x : probe.extents[handle - 4];
    // The blend handle sits on the inner box's +x+y edge, off the translate gizmo's x axis.
    if (handle == 7) {
        local.x = std::max(0.0f, probe.extents.x - probe.blendDistance);
        local.y = std::max(
            0.0f, (probe.shape == ProbeShape::Sphere ? probe.extents.x : probe.extents.y) - probe.blendDistance);
    }
    return glm::vec3(world * glm::vec4(local, 1.0f));
}

// The handle under the mouse: a translate axis (0-2), the plane (3), an extent (4-6; spheres
// have one, the radius) or the blend distance (7); -1 none.
int EditorApp::hitHandle(const render::CameraState& cam, glm::vec3 origin, float len, const glm::mat4& world,
                         const ReflectionProbe& probe) const {
    ImVec2 mouse = ImGui::GetIO().MousePos;
    float ox, oy;
    if (!project(cam, origin, ox, oy)) return -1;
    // The nearest handle within reach wins (handles can line up on screen).
    int hit = -1;
    float best = 1e30f;
    auto consider = [&](int h, float distance, float reach) {
        if (distance < reach && distance < best) best = distance, hit = h;
    };
    for (int a = 0; a < 3; ++a) {
        float ax, ay;
        if (project(cam, origin + axisVector(a) * len, ax, ay))
            consider(a, segmentDistance(mouse, {ox, oy}, {ax, ay}), 7.0f);
    }
    float px, py;
    if (project(cam, origin + (axisVector(0) + axisVector(2)) * (0.3f * len), px, py))
        consider(3, std::hypot(mouse.x - px, mouse.y - py), 10.0f);
    for (int h = 4; h <= 7; ++h) {
        if (probe.shape == ProbeShape::Sphere && (h == 5 || h == 6)) continue;
        if (project(cam, handlePosition(world, probe, h), px, py))
            consider(h, std::hypot(mouse.x - px, mouse.y - py), 8.0f);
    }
    return hit;
}

// Dragging an extent or the blend handle along its axis (node space); one command on release.
bool EditorApp::shapeDrag(const render::CameraState& cam, const Node& node, float mx, float my) {
    ReflectionProbe& p = drag_.probe;
    const ReflectionProbe& before = *node.probe;
    int axis = drag_.axis == 7 ? 0 : drag_.axis - 4;
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
        // Screen motion along the handle's axis, in node units: project one node unit.
        glm::vec3 at = handlePosition(node.world, before, drag_.axis);
        glm::vec3 unit = glm::vec3(node.world * glm::vec4(axisVector(axis), 0.0f));
        float ax, ay, bx, by;
        if (!project(cam, at, ax, ay) || !project(cam, at + unit, bx, by)) return true;
        float dx = bx - ax, dy = by - ay, d2 = std::max(1e-3f, dx * dx + dy * dy);
        float t = ((mx - drag_.mouseX) * dx + (my - drag_.mouseY) * dy) / d2;
        p = before;
        if (drag_.axis == 7) {
            p.blendDistance = std::clamp(before.blendDistance - t, 0.0f, before.extents.x);
        } else if (before.shape == ProbeShape::Sphere) {
            p.extents.x = std::max(0.01f, before.extents.x + t);
        } else {
            p.extents[axis] = std::max(0.01f, before.extents[axis] + t);
        }
        return true;
    }
    drag_.axis = -1;
    if (!(p == before)) {
        doc_.execute(setProbe(doc_, selectedNode_, p));
        status_ = "resized " + node.name;
        std::printf("speculum-editor: resized %s to extents %.4f %.4f %.4f blend %.4f\n", node.name.c_str(),
                    p.extents.x, p.extents.y, p.extents.z, p.blendDistance);
    }
    return true;
}

// Returns true while the gizmo owns the mouse (a drag started on a handle, or goes on).
bool EditorApp::gizmoInput(const render::CameraState& cam) {
    ImGuiIO& io = ImGui::GetIO();
    bool probeSelected = selectedNode_ >= 0 && doc_.scene().nodes[size_t(selectedNode_)].probe.has_value();
    if (!probeSelected) {
        drag_.axis = -1;
        return false;
    }
    glm::vec3 origin(doc_.scene().nodes[size_t(selectedNode_)].world[3]);
    float len = 0.15f * glm::length(origin - cam.position);
    float ox, oy;
    if (!project(cam, origin, ox, oy)) return false;
    ImVec2 mouse = io.MousePos;
    if (drag_.axis < 0) {
        if (!ImGui::IsMouseClicked(ImGuiMouseButton_Left) || io.WantCaptureMouse || io.KeyAlt ||
            !view_.contains(mouse.x, mouse.y))
            return false;
        const Node& n = doc_.scene().nodes[size_t(selectedNode_)];
        int hit = hitHandle(cam, origin, len, n.world, *n.probe);
        if (hit < 0) return false;
        drag_ = {hit, origin, origin, origin, mouse.x, mouse.y, *n.probe};
        return true;
    }
    const Node& node = doc_.scene().nodes[size_t(selectedNode_)];
    if (drag_.axis >= 4) return shapeDrag(cam, node, mouse.x, mouse.y);
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
        if (drag_.axis < 3) {
            float ax, ay, sx, sy;
            project(cam, drag_.start + axisVector(drag_.axis) * len, ax, ay);
            project(cam, drag_.start, sx, sy);
            float dx = ax - sx, dy = ay - sy, d2 = std::max(1e-3f, dx * dx + dy * dy);
            float t = ((mouse.x - drag_.mouseX) * dx + (mouse.y - drag_.mouseY) * dy) / d2;
            drag_.current = drag_.start + axisVector(drag_.axis) * (t * len);
        } else {
            // The xz plane through the start: where the mouse ray meets it, minus where the
            // ray met it at the press.
            auto hitPlane = [&](float mx, float my, glm::vec3& out) {
                glm::vec3 o, dir;
                render::primaryRay(cam, mx - view_.x - 0.5f, my - view_.y - 0.5f, o, dir);
                if (std::abs(dir.y) < 1e-4f) return false;
                float t = (drag_.start.y - o.y) / dir.y;
                if (t <= 0) return false;
                out = o + dir * t;
                return true;
            };
            glm::vec3 a, b;
            if (hitPlane(drag_.mouseX, drag_.mouseY, a) && hitPlane(mouse.x, mouse.y, b))
                drag_.current = drag_.start + (b - a);
        }
        // Live re-bake (time-sliced, one face a frame) from where the probe is now; the
        // release's command rebuilds and bakes it whole.
        if (drag_.current != drag_.sent) {
            glm::mat4 world = node.world;
            world[3] = glm::vec4(drag_.current, 1.0f);
            viewport_->moveProbeLive(selectedNode_, world);
            drag_.sent = drag_.current;
        }
        return true;
    }
    // Released: one command for the whole drag.
    glm::vec3 delta = drag_.current - drag_.start;
    drag_.axis = -1;
    if (glm::length(delta) > 0.0f) {
        const Node& n = doc_.scene().nodes[size_t(selectedNode_)];
        glm::mat3 parent = n.parent >= 0 ? glm::mat3(doc_.scene().nodes[size_t(n.parent)].world) : glm::mat3(1.0f);
        doc_.execute(moveNode(doc_, selectedNode_, n.translation + glm::inverse(parent) * delta));
        status_ = "moved " + n.name;
        glm::vec3 w(doc_.scene().nodes[size_t(selectedNode_)].world[3]);
        std::printf("speculum-editor: moved %s to %.4f %.4f %.4f\n", n.name.c_str(), w.x, w.y, w.z);
    }
    return true;
}

void EditorApp::drawOverlays(const render::CameraState& cam) {
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    dl->PushClipRect({view_.x, view_.y}, {view_.x + view_.w, view_.y + view_.h});
    const Scene& s = doc_.scene();
    auto line = [&](glm::vec3 a, glm::vec3 b, ImU32 color, float width) {
        float ax, ay, bx, by;
        if (project(cam, a, ax, ay) && project(cam, b, bx, by)) dl->AddLine({ax, ay}, {bx, by}, color, width);
    };
    for (size_t i = 0; i < s.nodes.size(); ++i) {
        const Node& n = s.nodes[i];
        if (!n.probe) continue;
        bool selected = int(i) == selectedNode_;
        glm::mat4 world = n.world;
        ImU32 color = selected ? IM_COL32(255, 210, 60, 255) : IM_COL32(80, 220, 230, 200);
        const ReflectionProbe& probe = selected && drag_.axis >= 4 ? drag_.probe : *n.probe;
        if (selected && drag_.axis >= 0 && drag_.axis < 4) world[3] = glm::vec4(drag_.current, 1.0f);
        glm::vec3 e = probe.extents;
        if (selected)
            for (int h = 4; h <= 7; ++h) {
                if (probe.shape == ProbeShape::Sphere && (h == 5 || h == 6)) continue;
                float hx, hy;
                if (!project(cam, handlePosition(world, probe, h), hx, hy)) continue;
                ImU32 c = h == drag_.axis ? IM_COL32(255, 255, 255, 255) : h == 7 ? IM_COL32(255, 150, 60, 230) : color;
                if (h == 7)
                    dl->AddCircleFilled({hx, hy}, 5.0f, c);
                else
                    dl->AddRectFilled({hx - 5, hy - 5}, {hx + 5, hy + 5}, c);
            }
        if (probe.shape == ProbeShape::Box) {
            // The influence box and, thinner, where the blend toward its border starts.
            for (float shrink : {0.0f, probe.blendDistance}) {
                glm::vec3 h = glm::max(e - shrink, glm::vec3(0.0f));
                auto corner = [&](int k) {
                    glm::vec3 c((k & 1) ? h.x : -h.x, (k & 2) ? h.y : -h.y, (k & 4) ? h.z : -h.z);
                    return glm::vec3(world * glm::vec4(c, 1.0f));
                };
                for (int k = 0; k < 8; ++k)
                    for (int bit : {1, 2, 4})
                        if (!(k & bit)) line(corner(k), corner(k | bit), color, shrink == 0.0f ? 1.5f : 0.7f);
            }
        } else {
            for (int axis = 0; axis < 3; ++axis)
                for (int k = 0; k < 48; ++k) {
                    auto at = [&](int j) {
                        float t = float(j) / 48.0f * 6.2831853f;
                        glm::vec3 p(0.0f);
                        p[(axis + 1) % 3] = std::cos(t) * e.x;
                        p[(axis + 2) % 3] = std::sin(t) * e.x;
                        return glm::vec3(world * glm::vec4(p, 1.0f));
                    };
                    line(at(k), at(k + 1), color, 1.2f);
                }
        }
        float cx, cy;
        if (project(cam, glm::vec3(world[3]), cx, cy)) {
            dl->AddCircleFilled({cx, cy}, 4.0f, color);
            dl->AddText({cx + 6, cy - 6}, color, n.name.c_str());
        }
    }
    if (selectedNode_ >= 0 && s.nodes[size_t(selectedNode_)].probe) {
        glm::vec3 origin = drag_.axis >= 0 ? drag_.current : glm::vec3(s.nodes[size_t(selectedNode_)].world[3]);
        float len = 0.15f * glm::length(origin - cam.position);
        for (int a = 0; a < 3; ++a)
            line(origin, origin + axisVector(a) * len, kAxisColors[a], drag_.axis == a ? 4.0f : 2.5f);
        float q[4][2];
        bool ok = true;
        const glm::vec3 corners[4] = {{0.2f, 0, 0.2f}, {0.4f, 0, 0.2f}, {0.4f, 0, 0.4f}, {0.2f, 0, 0.4f}};
        for (int k = 0; k < 4; ++k) ok &= project(cam, origin + corners[k] * len, q[k][0], q[k][1]);
        if (ok)
            dl->AddQuadFilled({q[0][0], q[0][1]}, {q[1][0], q[1][1]}, {q[2][0], q[2][1]}, {q[3][0], q[3][1]},
                              drag_.axis == 3 ? IM_COL32(255, 210, 60, 200) : IM_COL32(200, 200, 80, 120));
    }
    if (pick_.hit) {
        float px, py;
        if (project(cam, pick_.position, px, py)) dl->AddCircle({px, py}, 6.0f, IM_COL32(255, 255, 255, 200), 12, 1.5f);
    }
    dl->PopClipRect();
}

}  // namespace speculum::editor
