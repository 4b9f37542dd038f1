// Camera paths for multi-frame captures (assets/paths/*.json):
//   {"scene": "gallery", "frames": 24, "fov_deg": 55,
//    "keys": [{"eye": [x, y, z], "target": [x, y, z]}, ...]}
// Frame i interpolates the evenly spaced keys piecewise-linearly at t = i / (frames - 1).
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace speculum::app {

struct CameraPose {
    glm::vec3 eye{0.0f};
    glm::vec3 target{0.0f, 0.0f, -1.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovDeg = 55.0f;
};

// Throws Error(ExitCode::BadInput) naming the file and the problem.
std::vector<CameraPose> loadCameraPath(const std::filesystem::path& file);

}  // namespace speculum::app
