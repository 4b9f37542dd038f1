#include "camera.hpp"

#include <algorithm>
#include <cmath>

namespace speculum::editor {

glm::vec3 EditorCamera::forward() const {
    return {-std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_), -std::cos(yaw_) * std::cos(pitch_)};
}

void EditorCamera::setFromEyeAndForward(glm::vec3 eye, glm::vec3 dir, float distance) {
    dir = glm::normalize(dir);
    yaw_ = std::atan2(-dir.x, -dir.z);
    pitch_ = std::asin(std::clamp(dir.y, -1.0f, 1.0f));
    distance_ = std::max(distance, 0.05f);
    target_ = eye + dir * distance_;
}

void EditorCamera::reset(const Scene& scene) {
    float size = glm::length(scene.boundsMax - scene.boundsMin);
    speed_ = std::max(1.0f, 0.25f * size);
    if (!scene.cameras.empty()) {
        useNamed(scene.cameras.front());
        return;
    }
    named_.clear();
    frame(scene.boundsMin, scene.boundsMax);
}

void EditorCamera::useNamed(const Camera& camera) {
    glm::vec3 eye(camera.world[3]);
    glm::vec3 dir = -glm::vec3(camera.world[2]);
    setFromEyeAndForward(eye, dir, std::max(1.0f, distance_));
    yfov_ = camera.yfov;
    named_ = camera.name;
    namedCamera_ = camera;
}

void EditorCamera::orbit(float dx, float dy) {
    yaw_ -= dx * 0.005f;
    pitch_ = std::clamp(pitch_ - dy * 0.005f, -1.55f, 1.55f);
    named_.clear();
}

void EditorCamera::look(float dx, float dy) {
    glm::vec3 e = eye();
    yaw_ -= dx * 0.003f;
    pitch_ = std::clamp(pitch_ - dy * 0.003f, -1.55f, 1.55f);
    target_ = e + forward() * distance_;
    named_.clear();
}

void EditorCamera::pan(float dx, float dy, float viewportHeight) {
    glm::vec3 f = forward();
    glm::vec3 r = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
    glm::vec3 u = glm::cross(r, f);
    // One pixel moves the target by one pixel's size at the target's distance.
    float perPixel = 2.0f * distance_ * std::tan(0.5f * yfov_) / std::max(1.0f, viewportHeight);
    target_ += (-dx * r + dy * u) * perPixel;
    named_.clear();
}

void EditorCamera::zoom(float wheel) {
    distance_ = std::clamp(distance_ * std::pow(0.85f, wheel), 0.05f, 1e5f);
    named_.clear();
}

void EditorCamera::fly(glm::vec3 move, float seconds) {
    if (move == glm::vec3(0.0f)) return;
    glm::vec3 f = forward();
    glm::vec3 r = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
    target_ += (r * move.x + glm::vec3(0, 1, 0) * move.y + f * move.z) * speed_ * seconds;
    named_.clear();
}

void EditorCamera::frame(glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 centre = 0.5f * (lo + hi);
    float radius = std::max(0.25f, 0.5f * glm::length(hi - lo));
    if (distance_ <= 0.0f || named_.size()) pitch_ = -0.35f;
    target_ = centre;
    distance_ = radius / std::sin(0.5f * yfov_) * 1.1f;
    named_.clear();
}

render::CameraState EditorCamera::state(uint32_t width, uint32_t height) const {
    if (!named_.empty()) return render::makeCamera(namedCamera_, width, height);
    glm::vec3 e = eye();
    return render::makeCamera(e, e + forward(), {0, 1, 0}, yfov_, width, height);
}

}  // namespace speculum::editor
