// The CLI11 options the tools share: the camera flags (camera_flags.hpp) and the settings
// flags; header-only, so that a tool needs no extra library.
#pragma once

#include "speculum/app/camera_flags.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace speculum::app {

// The scene and camera flags speculum-capture and speculum-reference share, so that both
// tools frame exactly the same views for the same flags (selectCameras).
inline void addCameraOptions(CLI::App& cli, CameraFlags& flags, std::string& size) {
    cli.add_option("--scene", flags.scenePath, "glTF scene (.gltf or .glb)");
    cli.add_option("--camera", flags.camera, "camera by glTF name");
    cli.add_option("--eye", flags.eye, "camera position X,Y,Z");
    cli.add_option("--target", flags.target, "point looked at X,Y,Z");
    cli.add_option("--up", flags.up, "up vector X,Y,Z (default 0,1,0)");
    cli.add_option("--fov", flags.fov, "vertical field of view in degrees (with --eye; default 60)");
    cli.add_option("--path", flags.path, "JSON camera path: one output frame per path frame");
    cli.add_option("--size", size, "image size WxH (default 960x540)");
}

// --settings FILE and --set KEY=VALUE (repeatable), applied by the tool after parsing; `uses`
// says which settings the tool reads ("" all).
inline void addSettingsOptions(CLI::App& cli, std::string& file, std::vector<std::string>& sets,
                               const std::string& uses = "") {
    const std::string used = uses.empty() ? "" : uses + " is used";
    cli.add_option("--settings", file, "JSON settings file" + (used.empty() ? "" : " (" + used + ")"));
    cli.add_option("--set", sets, "KEY=VALUE setting (repeatable" + (used.empty() ? "" : "; " + used) + ")");
}

}  // namespace speculum::app
