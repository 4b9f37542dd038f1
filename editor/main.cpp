// speculum-editor [--scene FILE] [--script FILE]: place probes, tune materials and settings,
// see every module's debug views, save without ever losing the scene (editor/README.md).
#include "app.hpp"

#include "speculum/app/camera_flags.hpp"
#include "speculum/app/tool_main.hpp"
#include "speculum/core.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

using namespace speculum;

int main(int argc, char** argv) {
    editor::Options o;
    o.scene = std::string(SPECULUM_SOURCE_DIR) + "/assets/scenes/gallery.gltf";
    std::string scene = o.scene.string(), script, size = "1280x720";
    CLI::App cli{"speculum-editor: place probes, tune reflections per material, see every method at work"};
    cli.add_option("--scene", scene, "glTF scene (.gltf or .glb; default: the gallery)");
    cli.add_option("--script", script, "JSON list of UI actions to replay (editor/README.md)");
    cli.add_option("--device", o.device, "Vulkan device name (substring)");
    cli.add_option("--size", size, "window size WxH (default 1280x720)");
    cli.add_option("--recover", o.recover, "a newer autosave on start: ask (a dialog), yes (load it), no")
        ->check(CLI::IsMember({"ask", "yes", "no"}));
    return app::toolMain("speculum-editor", cli, argc, argv, [&] {
        if (script.empty() && cli.count("--script")) throw argumentError("--script needs a file name, got \"\"");
        o.scene = scene;
        o.script = script;
        auto [w, h] = app::parseSize(size);
        o.width = w;
        o.height = h;
        return editor::run(o);
    });
}
