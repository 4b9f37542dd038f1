// The viewport's camera: orbit around a target, pan, zoom, fly (look from the eye and move),
// frame a box, or sit exactly on one of the scene's named cameras (so that the viewport shows
// what speculum-capture --camera NAME shows).
#pragma once

#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"

#include <glm/glm.hpp>

#include <string>

namespace speculum::editor {

class EditorCamera {
public:
    // Frames the scene's bounds, or sits on its first camera when it has one.
    void reset(const Scene& scene);
    void orbit(float dx, float dy);  // pixels of mouse motion
    void pan(float dx, float dy, float viewportHeight);
    void zoom(float wheel);
    void look(float dx, float dy);                 // rotates about the eye
    void fly(glm::vec3 localMove, float seconds);  // x right, y up, z forward
    void frame(glm::vec3 boundsMin, glm::vec3 boundsMax);
    void useNamed(const Camera& camera);

    // The named camera this view still equals ("" once the user moved it).
    const std::string& named() const { return named_; }
    glm::vec3 eye() const { return target_ - forward() * distance_; }
    glm::vec3 target() const { return target_; }
    glm::vec3 forward() const;
    render::CameraState state(uint32_t width, uint32_t height) const;
    float flySpeed() const { return speed_; }

private:
    void setFromEyeAndForward(glm::vec3 eye, glm::vec3 forward, float distance);
    glm::vec3 target_{0.0f};
    float distance_ = 5.0f;
    float yaw_ = 0.0f;    // radians; 0 looks down -Z
    float pitch_ = 0.0f;  // radians
    float yfov_ = 0.8f;
    float speed_ = 2.0f;  // fly speed, world units per second
    std::string named_;
    Camera namedCamera_;
};

}  // namespace speculum::editor
