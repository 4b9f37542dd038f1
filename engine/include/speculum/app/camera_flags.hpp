// The scene-and-camera command-line flags that speculum-capture and speculum-reference share
// (docs/design.md section 6, command lines): parsing of lists, vectors and sizes, and the choice of camera per
// output frame, so that both tools render exactly the same views for the same flags.
#pragma once

#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"

#include <string>
#include <utility>
#include <vector>

namespace speculum::app {

// "a,b,,c" -> {"a", "b", "c"}.
std::vector<std::string> splitList(const std::string& s);
// "X,Y,Z"; throws Error(BadArguments) naming the flag.
glm::vec3 parseVec3(const std::string& s, const char* flag);
// "WxH", decimal digits only, both in 1..kMaxImageSide; throws Error(BadArguments) with the text.
// The device's own maxImageDimension2D is checked once it is known.
inline constexpr uint64_t kMaxImageSide = 65536;
std::pair<uint32_t, uint32_t> parseSize(const std::string& s);

struct CameraFlags {
    std::string scenePath;  // for messages
    std::string camera, eye, target, up = "0,1,0", path;
    float fov = 60.0f;
};

// One camera per output frame: the path's frames; else `frames` copies of the named camera,
// of --eye/--target, or of a framing of the scene's bounds. Throws Error(BadArguments).
std::vector<render::CameraState> selectCameras(const CameraFlags& flags, const Scene& scene, uint32_t width,
                                               uint32_t height, size_t frames);

}  // namespace speculum::app
