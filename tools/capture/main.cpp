// speculum-capture: headless renders of a scene to EXR/PNG AOVs plus timings.json.
// Contract: docs/design.md section 6 (command-line contracts). Exit 0 done, 2 bad arguments,
// 3 bad scene or settings, 4 no usable Vulkan device.
#include "speculum/app/camera_flags.hpp"
#include "speculum/app/camera_options.hpp"
#include "speculum/app/device_budget.hpp"
#include "speculum/app/engine_settings.hpp"
#include "speculum/app/frame_runner.hpp"
#include "speculum/app/output.hpp"
#include "speculum/app/tool_main.hpp"
#include "speculum/chain.hpp"
#include "speculum/core.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using namespace speculum;

namespace {

struct Options {
    app::CameraFlags view;  // --scene, --camera, --eye, --target, --up, --fov, --path
    std::string size = "960x540", settingsFile, out, device;
    std::string aov = "color";
    int frames = 1;
    int warmup = 3;
    std::vector<std::string> sets;
    bool settingsGiven = false, framesGiven = false;  // a flag given as "" or beside --path
};

// Every AOV this tool can write: the engine's, then the hosted modules' (their ModuleInfo).
std::string knownAovs(const char* separator) {
    std::string known;
    for (const std::string& a : app::availableAovs()) known += (known.empty() ? "" : separator) + a;
    for (const app::ModuleInfo& m : chain::moduleInfos())
        for (const app::AovInfo& a : m.aovs) known += separator + a.name;
    return known;
}

std::vector<std::string> parseAovs(const std::string& list) {
    auto aovs = app::splitList(list);
    const std::vector<app::ModuleInfo> mods = chain::moduleInfos();
    const std::string known = knownAovs(", ");
    if (aovs.empty()) throw argumentError("--aov needs at least one of: " + known);
    for (const std::string& a : aovs) {
        const auto& engine = app::availableAovs();
        if (std::find(engine.begin(), engine.end(), a) == engine.end() && !app::aovProvider(mods, a))
            throw argumentError("unknown AOV '" + a + "' (known: " + known + ")");
    }
    return aovs;
}

// The files a run will write, where a folder of that name would stop it only after rendering.
void checkOutputNames(const std::string& out, const std::vector<std::string>& aovs, size_t frames, bool everyFrame) {
    std::vector<std::string> names = {"timings.json", "graph.dot", "graph.json"};
    for (size_t f : {everyFrame ? size_t(0) : frames - 1, frames - 1})
        for (const std::string& a : aovs) {
            char stem[64];
            std::snprintf(stem, sizeof stem, ".%04zu", f);
            names.push_back(a + stem + ".exr");
            if (a == "color") names.push_back(a + stem + ".png");
        }
    for (const std::string& n : names)
        if (fs::is_directory(fs::path(out) / n))
            throw argumentError("--out " + out + ": " + n + " is a folder; the capture writes a file of that name");
}

int run(const Options& o) {
    if (o.out.empty()) throw argumentError("--out DIR is required");
    if (o.view.scenePath.empty()) throw argumentError("--scene FILE is required");
    if (o.frames < 1 || o.frames > 100000) throw argumentError("--frames must be in 1..100000");
    if (o.warmup < 0 || o.warmup > 1000) throw argumentError("--warmup must be in 0..1000");
    if (o.framesGiven && !o.view.path.empty())
        throw argumentError(
            "--frames does not apply with --path: the path's \"frames\" sets how many frames are rendered");
    if (o.settingsGiven && o.settingsFile.empty()) throw argumentError("--settings needs a file name, got \"\"");
    auto [w, h] = app::parseSize(o.size);
    std::vector<std::string> aovs = parseAovs(o.aov);

    Settings settings(app::settingsOf(app::engineSettingsTable(), chain::moduleInfos()));
    if (o.settingsGiven) settings.load(o.settingsFile);
    for (const std::string& kv : o.sets) settings.assign(kv);

    Scene scene = loadScene(o.view.scenePath);
    std::vector<render::CameraState> cameras = app::selectCameras(
        o.view, scene, w, h, size_t(o.frames));
    app::prepareOutputDir(o.out);  // before the device: a bad --out costs no rendering
    checkOutputNames(o.out, aovs, cameras.size(), !o.view.path.empty());

    gpu::Context ctx(gpu::ContextOptions{.deviceName = o.device});
    uint32_t maxDim = ctx.properties().limits.maxImageDimension2D;
    if (w > maxDim || h > maxDim)
        throw argumentError("--size " + o.size + " exceeds the device limit of " + std::to_string(maxDim) + " pixels (" +
                            ctx.deviceName() + ")");
    app::checkSceneFitsDevice(ctx, scene);

    render::Renderer renderer(ctx, scene, fromSettings<render::RendererOptions>(settings));
    chain::Chain modules(ctx, renderer, settings);
    const probes::Probes& probeModule = modules.probes();
    app::FrameRunner runner(ctx, renderer, w, h);
    // Probes update before each frame's graph is built (their captures are graphs of their own).
    auto updateProbes = [&] { modules.update(settings, probes::Probes::terminalProgress()); };

    // Warm-up frames compile every pipeline (lavapipe compiles at first submit) before timing.
    render::FrameInputs frame;
    frame.camera = frame.previousCamera = cameras.front();
    for (int i = 0; i < o.warmup; ++i) {
        updateProbes();
        runner.render(frame, {}, modules.litHook(settings, frame));
    }

    app::TimingLog timings;
    bool writeEvery = !o.view.path.empty();
    for (size_t i = 0; i < cameras.size(); ++i) {
        frame.previousCamera = frame.camera;
        frame.camera = cameras[i];
        if (i == 0) frame.previousCamera = frame.camera;
        bool write = writeEvery || i + 1 == cameras.size();
        updateProbes();
        app::FrameResult result = runner.render(frame, write ? aovs : std::vector<std::string>{},
                                                modules.litHook(settings, frame));
        // The planar probes render this frame's mirrored views in a graph of their own before it
        // (Probes::renderPlanar): their GPU time is a pass of the frame, first, and in its total.
        if (!probeModule.planars().empty()) {
            result.passes.insert(result.passes.begin(), app::PassTime{"probes.planar", probeModule.planarMs()});
            result.frameMs += probeModule.planarMs();
        }
        timings.add(result);
        if (write)
            for (const auto& [name, image] : result.aovs) app::writeAov(o.out, name, int(i), image);
        if (cameras.size() > 1) app::progress("capture", i + 1, cameras.size());
    }
    app::writeText(fs::path(o.out) / "graph.dot", runner.graphDot());
    nlohmann::json graph = runner.graphJson();
    for (auto& pass : graph["passes"]) pass["median_ms"] = timings.medianPassMs(pass.value("name", ""));
    app::writeText(fs::path(o.out) / "graph.json", graph.dump(2));
    nlohmann::json timing = timings.toJson(ctx.deviceName(), w, h, gpu::persistentBytes());
    // Probe captures run in graphs of their own, outside the frame's passes: their GPU time and
    // the prefilters' wall time, over every update of the run (warm-up included).
    timing["probes"] = {{"count", probeModule.probes().size()},
                        {"faces_captured", probeModule.facesCaptured()},
                        {"capture_ms", probeModule.captureMs()}};
    app::writeText(fs::path(o.out) / "timings.json", timing.dump(2));
    if (probeModule.facesCaptured() > 0)
        std::cout << "probes: " << probeModule.probes().size() << " probes, " << probeModule.facesCaptured()
                  << " faces captured and prefiltered in " << probeModule.captureMs() << " ms\n";
    std::cout << timings.summary() << std::flush;
    if (ctx.validationEnabled() && gpu::Context::validationMessageCount() > 0) {
        logError(std::to_string(gpu::Context::validationMessageCount()) + " Vulkan validation messages");
        return static_cast<int>(ExitCode::Failure);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App cli{"speculum-capture: render a glTF scene headless to EXR/PNG AOVs and timings.json"};
    app::addCameraOptions(cli, o.view, o.size);
    cli.add_option("--frames", o.frames, "frames to render and time (default 1; not with --path)");
    cli.add_option("--warmup", o.warmup, "untimed frames first (default 3)");
    app::addSettingsOptions(cli, o.settingsFile, o.sets);
    const std::string aovHelp = "comma list: " + knownAovs(",") + " (default color)";
    cli.add_option("--aov", o.aov, aovHelp);
    cli.add_option("--out", o.out, "output directory");
    cli.add_option("--device", o.device, "Vulkan device name (substring)");
    return app::toolMain("speculum-capture", cli, argc, argv, [&] {
        o.settingsGiven = cli.count("--settings") > 0;
        o.framesGiven = cli.count("--frames") > 0;
        return run(o);
    });
}
