// Camera conventions on the CPU: primaryRay must trace exactly what the rasterizer samples.
#include "speculum/render/renderer.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <random>

namespace speculum::render {
namespace {

// Pixel coordinates (centre of pixel (x, y) is (x, y) for primaryRay) a world point projects to.
glm::vec3 projectToPixel(const CameraState& c, glm::vec3 world) {
    glm::dvec4 clip = glm::dmat4(c.viewProj) * glm::dvec4(glm::dvec3(world), 1.0);
    glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
    return glm::vec3(float((ndc.x * 0.5 + 0.5) * c.width - 0.5),
                     float((ndc.y * 0.5 + 0.5) * c.height - 0.5), float(ndc.z));
}

void expectRayHits(const CameraState& c, glm::vec3 world) {
    glm::vec3 px = projectToPixel(c, world);
    glm::vec3 origin, dir;
    primaryRay(c, px.x, px.y, origin, dir);
    EXPECT_NEAR(glm::length(dir), 1.0f, 1e-5f);
    glm::vec3 toPoint = world - origin;
    float along = glm::dot(toPoint, dir);
    EXPECT_GT(along, 0.0f);
    float miss = glm::length(toPoint - along * dir);
    EXPECT_LT(miss, 1e-4f * std::max(1.0f, along)) << "pixel " << px.x << "," << px.y;
}

TEST(RenderCamera, PrimaryRayHitsThePointThatProjectsToThePixel) {
    CameraState c = makeCamera({1, 2, 5}, {0, 0.5f, 0}, {0, 1, 0}, 0.9f, 960, 540);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 200; ++i) {
        glm::vec3 p(u(rng) * 3.0f, u(rng) * 2.0f, u(rng) * 3.0f);
        if (projectToPixel(c, p).z <= 0.0f || projectToPixel(c, p).z > 1.0f) continue;
        expectRayHits(c, p);
    }
}

TEST(RenderCamera, PixelCentresAndOrientation) {
    CameraState c = makeCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.8f, 64, 32);
    glm::vec3 origin, dir;
    // The centre of the image lies between pixels 31 and 32: pixel 31.5 looks straight ahead.
    primaryRay(c, 31.5f, 15.5f, origin, dir);
    EXPECT_NEAR(dir.x, 0.0f, 1e-6f);
    EXPECT_NEAR(dir.y, 0.0f, 1e-6f);
    EXPECT_NEAR(dir.z, -1.0f, 1e-6f);
    // World +Y is up on screen (smaller y), +X to the right.
    EXPECT_LT(projectToPixel(c, {0, 1, 0}).y, 15.5f);
    EXPECT_GT(projectToPixel(c, {1, 0, 0}).x, 31.5f);
    // Reversed-Z, infinite far: 1 at the near plane, towards 0 far away.
    EXPECT_NEAR(projectToPixel(c, {0, 0, 5.0f - c.znear}).z, 1.0f, 1e-5f);
    EXPECT_LT(projectToPixel(c, {0, 0, -1e6f}).z, 1e-6f);
    EXPECT_GT(projectToPixel(c, {0, 0, -1e6f}).z, 0.0f);
}

TEST(RenderCamera, GltfCamerasPerspectiveAndOrthographic) {
    Camera cam;
    cam.world = glm::translate(glm::mat4(1.0f), glm::vec3(0, 1, 4));
    cam.yfov = 0.7f;
    CameraState p = makeCamera(cam, 200, 100);
    EXPECT_NEAR(p.proj[0][0] * 2.0f, -p.proj[1][1], 1e-5f);  // aspect from the viewport
    EXPECT_NEAR(p.position.y, 1.0f, 1e-6f);
    expectRayHits(p, {0.3f, 1.2f, 0.0f});

    cam.perspective = false;
    cam.xmag = 2.0f;
    cam.ymag = 1.0f;
    cam.zfar = 50.0f;
    CameraState o = makeCamera(cam, 200, 100);
    glm::vec3 origin, dir;
    primaryRay(o, 10.0f, 80.0f, origin, dir);
    EXPECT_NEAR(dir.z, -1.0f, 1e-5f);  // parallel rays
    expectRayHits(o, {0.5f, 0.6f, -3.0f});
    expectRayHits(o, {-1.5f, 1.8f, -20.0f});
}

TEST(RenderCamera, FrameBoundsSeesTheWholeScene) {
    Scene scene;
    scene.boundsMin = {-1, 0, -2};
    scene.boundsMax = {3, 1, 2};
    CameraState c = frameBounds(scene, 320, 180);
    for (int i = 0; i < 8; ++i) {
        glm::vec3 corner((i & 1) ? 3 : -1, (i & 2) ? 1 : 0, (i & 4) ? 2 : -2);
        glm::vec3 px = projectToPixel(c, corner);
        EXPECT_GT(px.x, -0.5f);
        EXPECT_LT(px.x, 319.5f);
        EXPECT_GT(px.y, -0.5f);
        EXPECT_LT(px.y, 179.5f);
        EXPECT_GT(px.z, 0.0f);
        EXPECT_LE(px.z, 1.0f);
    }
}

}  // namespace
}  // namespace speculum::render
