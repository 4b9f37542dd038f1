#include "speculum/app/camera_flags.hpp"

#include "speculum/app/camera_path.hpp"
#include "speculum/core.hpp"

#include <glm/glm.hpp>

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace speculum::app {

std::vector<std::string> splitList(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

glm::vec3 parseVec3(const std::string& s, const char* flag) {
    auto parts = splitList(s);
    glm::vec3 v;
    if (parts.size() != 3) throw argumentError(std::string(flag) + " needs X,Y,Z, got '" + s + "'");
    for (int i = 0; i < 3; ++i) {
        try {
            size_t used = 0;
            v[i] = std::stof(parts[size_t(i)], &used);
            if (used != parts[size_t(i)].size()) throw std::invalid_argument("trailing");
        } catch (const std::exception&) {
            throw argumentError(std::string(flag) + " needs three numbers X,Y,Z, got '" + s + "'");
        }
    }
    return v;
}

std::pair<uint32_t, uint32_t> parseSize(const std::string& s) {
    // Digits only, by hand: sscanf's %u took "-3" as 4294967293 and wrapped 4294967296 to 0.
    auto number = [&](size_t& i, uint64_t& v) {
        size_t start = i;
        for (v = 0; i < s.size() && s[i] >= '0' && s[i] <= '9' && i - start < 12; ++i)
            v = v * 10 + uint64_t(s[i] - '0');
        return i > start && (i >= s.size() || s[i] < '0' || s[i] > '9');
    };
    size_t i = 0;
    uint64_t w = 0, h = 0;
    bool ok = number(i, w) && i < s.size() && (s[i] == 'x' || s[i] == 'X') && number(++i, h) && i == s.size();
    if (!ok) throw argumentError("--size needs WxH with two whole numbers (e.g. 960x540), got '" + s + "'");
    if (w == 0 || h == 0) throw argumentError("--size " + s + " is empty: width and height must be at least 1");
    if (w > kMaxImageSide || h > kMaxImageSide)
        throw argumentError("--size " + s + " exceeds every device limit: more than " + std::to_string(kMaxImageSide) +
                            " pixels on a side");
    return {uint32_t(w), uint32_t(h)};
}

std::vector<render::CameraState> selectCameras(const CameraFlags& f, const Scene& scene, uint32_t w, uint32_t h,
                                               size_t frames) {
    if (!f.path.empty()) {
        if (!f.camera.empty() || !f.eye.empty()) throw argumentError("--path replaces --camera and --eye: give one");
        std::vector<render::CameraState> out;
        for (const CameraPose& p : loadCameraPath(f.path))
            out.push_back(render::makeCamera(p.eye, p.target, p.up, glm::radians(p.fovDeg), w, h));
        return out;
    }
    if (!f.camera.empty()) {
        const Camera* cam = scene.findCamera(f.camera);
        if (!cam) {
            std::string names;
            for (const Camera& c : scene.cameras) names += (names.empty() ? "" : ", ") + c.name;
            throw argumentError("scene " + f.scenePath + " has no camera named '" + f.camera + "' (cameras: " +
                                (names.empty() ? "none" : names) + ")");
        }
        return std::vector<render::CameraState>(frames, render::makeCamera(*cam, w, h));
    }
    if (!f.eye.empty() || !f.target.empty()) {
        if (f.eye.empty() || f.target.empty()) throw argumentError("--eye and --target go together");
        glm::vec3 eye = parseVec3(f.eye, "--eye"), target = parseVec3(f.target, "--target");
        glm::vec3 up = parseVec3(f.up, "--up");
        if (glm::length(target - eye) < 1e-6f) throw argumentError("--eye and --target are the same point");
        if (!(f.fov > 1.0f && f.fov < 179.0f)) throw argumentError("--fov must be in 1..179 degrees");
        return std::vector<render::CameraState>(frames,
                                                render::makeCamera(eye, target, up, glm::radians(f.fov), w, h));
    }
    return std::vector<render::CameraState>(frames, render::frameBounds(scene, w, h));
}

}  // namespace speculum::app
