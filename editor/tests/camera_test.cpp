// The viewport's camera without a device: a named camera gives exactly the capture tool's view,
// and orbit, pan, zoom and framing do what they say.
#include "../camera.hpp"

#include <gtest/gtest.h>

namespace speculum::editor {
namespace {

Scene sceneWithCamera() {
    Scene s;
    Camera c;
    c.name = "main";
    c.yfov = 0.9f;
    c.world = glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 2.0f, 5.0f)) *
              glm::mat4_cast(glm::angleAxis(0.3f, glm::vec3(0.0f, 1.0f, 0.0f)));
    s.cameras.push_back(c);
    s.boundsMin = glm::vec3(-2.0f);
    s.boundsMax = glm::vec3(2.0f);
    return s;
}

TEST(EditorCamera, NamedCameraIsTheCapturesView) {
    Scene s = sceneWithCamera();
    EditorCamera cam;
    cam.reset(s);
    EXPECT_EQ(cam.named(), "main");
    render::CameraState want = render::makeCamera(s.cameras[0], 640, 360);
    render::CameraState got = cam.state(640, 360);
    EXPECT_EQ(got.viewProj, want.viewProj);
    EXPECT_NEAR(glm::distance(cam.eye(), glm::vec3(1.0f, 2.0f, 5.0f)), 0.0f, 1e-4f);
    cam.orbit(10.0f, 0.0f);
    EXPECT_EQ(cam.named(), "") << "moving leaves the named camera";
}

TEST(EditorCamera, OrbitKeepsTheTargetZoomKeepsTheDirection) {
    EditorCamera cam;
    cam.frame(glm::vec3(-1.0f), glm::vec3(1.0f));
    glm::vec3 target = cam.target();
    float d = glm::distance(cam.eye(), target);
    cam.orbit(120.0f, 30.0f);
    EXPECT_NEAR(glm::distance(cam.target(), target), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(cam.eye(), target), d, 1e-4f);
    glm::vec3 f = cam.forward();
    cam.zoom(2.0f);
    EXPECT_LT(glm::distance(cam.eye(), target), d);
    EXPECT_NEAR(glm::distance(cam.forward(), f), 0.0f, 1e-6f);
    // Framed: the whole box is in front of the camera, inside the field of view.
    cam.frame(glm::vec3(9.0f), glm::vec3(11.0f));
    render::CameraState st = cam.state(400, 400);
    for (int k = 0; k < 8; ++k) {
        glm::vec3 c((k & 1) ? 11.0f : 9.0f, (k & 2) ? 11.0f : 9.0f, (k & 4) ? 11.0f : 9.0f);
        glm::vec4 clip = st.viewProj * glm::vec4(c, 1.0f);
        ASSERT_GT(clip.w, 0.0f);
        EXPECT_LE(std::abs(clip.x / clip.w), 1.0f);
        EXPECT_LE(std::abs(clip.y / clip.w), 1.0f);
    }
}

TEST(EditorCamera, PanMovesTargetAndEyeTogether) {
    EditorCamera cam;
    cam.frame(glm::vec3(-1.0f), glm::vec3(1.0f));
    glm::vec3 offset = cam.eye() - cam.target();
    glm::vec3 before = cam.target();
    cam.pan(50.0f, 0.0f, 500.0f);
    EXPECT_GT(glm::distance(cam.target(), before), 0.0f);
    EXPECT_NEAR(glm::distance(cam.eye() - cam.target(), offset), 0.0f, 1e-5f);
}

}  // namespace
}  // namespace speculum::editor
