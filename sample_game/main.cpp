// speculum-game: walk the hall of mirrors and find the collectibles, which only the mirrors show
// (sample_game/README.md: controls, recordings, frame rates). The HUD (Dear ImGui, the editor's
// UI layer) shows fps and GPU time and toggles each reflection method; the internal resolution
// follows the frame time and the image is upscaled to the window.
#include "game.hpp"
#include "ui_layer.hpp"

#include "speculum/app/device_budget.hpp"
#include "speculum/app/camera_flags.hpp"
#include "speculum/app/frame_runner.hpp"
#include "speculum/app/output.hpp"
#include "speculum/app/window.hpp"
#include "speculum/core.hpp"
#include "speculum/reflections/hook.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"

#include <CLI/CLI.hpp>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

using namespace speculum;

namespace {

const std::string kSourceDir = SPECULUM_SOURCE_DIR;
const char* const kPresets[] = {"low", "medium", "high"};
// Frame-time goal of the dynamic resolution: 15 fps with a margin.
constexpr double kTargetMs = 1000.0 / 15.0 * 0.85;
constexpr float kMinScale = 0.15f, kScaleStep = 0.05f;

struct Options {
    std::string scene = kSourceDir + "/assets/scenes/hall_of_mirrors.gltf";
    std::string device;
    int frames = 0;
    std::string size = "1280x720";
    std::string preset = "low";
    float scale = 0.0f;  // 0: dynamic
    std::string record, replay;
    std::string shots;
    std::set<int> shotFrames;
    std::vector<std::string> sets;  // KEY=VALUE over the preset
};

// Resident set size now, from /proc/self/statm (pages), in MB; 0 where there is no /proc.
double residentMb() {
    std::ifstream statm("/proc/self/statm");
    unsigned long long size = 0, resident = 0;
    if (!(statm >> size >> resident)) return 0.0;
    return double(resident) * double(sysconf(_SC_PAGESIZE)) / 1048576.0;
}

std::string sceneFile(const std::string& name) {
    if (std::filesystem::exists(name)) return name;
    return kSourceDir + "/assets/scenes/" + name;
}

void loadPreset(Settings& settings, const std::string& preset) {
    std::filesystem::path file = kSourceDir + "/assets/settings/" + preset + ".json";
    if (!std::filesystem::is_regular_file(file))
        throw argumentError("--preset " + preset + ": expected low, medium or high (" + file.string() + ")");
    settings.load(file);
}

// Live input: WASD and space while playing; the mouse looks while the cursor is captured.
game::FrameInput liveInput(GLFWwindow* w, bool playing, double& lastX, double& lastY) {
    game::FrameInput in;
    double x, y;
    glfwGetCursorPos(w, &x, &y);
    if (playing && glfwGetInputMode(w, GLFW_CURSOR) == GLFW_CURSOR_DISABLED) {
        in.dx = float(x - lastX);
        in.dy = float(y - lastY);
    }
    lastX = x;
    lastY = y;
    if (!playing) return in;
    auto held = [&](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
    in.keys = (held(GLFW_KEY_W) ? game::kForward : 0u) | (held(GLFW_KEY_S) ? game::kBack : 0u) |
              (held(GLFW_KEY_A) ? game::kLeft : 0u) | (held(GLFW_KEY_D) ? game::kRight : 0u) |
              (held(GLFW_KEY_SPACE) ? game::kJump : 0u);
    return in;
}

// The frame's image blitted (bilinear) over the whole window, then the HUD over it.
void addPresentPasses(FrameGraph& g, TextureHandle color, app::Swapchain& swapchain, editor::UiLayer& ui) {
    VkExtent2D extent = swapchain.extent();
    TextureDesc desc{.width = extent.width, .height = extent.height, .format = swapchain.format()};
    TextureHandle target =
        g.importTexture("game.swapchain", desc,
                        {swapchain.image(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                         VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    struct Data {
        TextureHandle src, dst;
    };
    const Data& d = g.addPass<Data>(
        "game.upscale", PassType::Transfer,
        [&](PassBuilder& b, Data& data) {
            data.src = b.read(color, TextureUsage::TransferSrc);
            data.dst = b.write(target, TextureUsage::TransferDst);
        },
        [](const Data& data, PassContext& pc) {
            VkExtent2D s = pc.extent(data.src), t = pc.extent(data.dst);
            VkImageBlit blit{};
            blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            blit.srcOffsets[1] = {int32_t(s.width), int32_t(s.height), 1};
            blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            blit.dstOffsets[1] = {int32_t(t.width), int32_t(t.height), 1};
            vkCmdBlitImage(pc.cmd(), pc.image(data.src), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pc.image(data.dst),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
        });
    ui.addPass(g, d.dst);
}

struct Hud {
    double fps = 0.0, gpuMs = 0.0;
    int preset = 0;
    bool paused = false;
};

void checkbox(Settings& settings, const char* label, const std::string& name) {
    bool v = settings.getBool(name);
    if (ImGui::Checkbox(label, &v)) settings.set(name, v ? 1.0 : 0.0);
}

void drawHud(Hud& hud, Settings& settings, const game::Game& game, VkExtent2D window, VkExtent2D internal,
             bool replaying) {
    ImGui::SetNextWindowPos({8, 8}, ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("HUD", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoFocusOnAppearing);
    ImGui::Text("found %d / %d   time %.1f s", game.taken(), int(game.collectibles().size()), game.time());
    ImGui::Text("%.1f fps   GPU %.1f ms   %ux%u -> %ux%u", hud.fps, hud.gpuMs, internal.width, internal.height,
                window.width, window.height);
    if (ImGui::Combo("preset", &hud.preset, kPresets, 3)) loadPreset(settings, kPresets[hud.preset]);
    checkbox(settings, "screen space", "reflections.screen_space");
    ImGui::SameLine();
    checkbox(settings, "CMOs", "reflections.cmos");
    ImGui::SameLine();
    checkbox(settings, "probes", "reflections.probes");
    ImGui::SameLine();
    checkbox(settings, "temporal", "reflections.temporal");
    if (const SettingDesc* dv = settings.find("reflections.debug_view")) {
        int view = settings.getInt(dv->name);
        std::vector<const char*> names;
        for (const std::string& c : dv->choices) names.push_back(c.c_str());
        if (ImGui::Combo("debug view", &view, names.data(), int(names.size()))) settings.set(dv->name, double(view));
    }
    ImGui::TextDisabled(replaying ? "replaying a recording" : "Esc: pause menu and controls");
    ImGui::End();
    ImVec2 centre(float(window.width) * 0.5f, float(window.height) * 0.5f);
    if (game.won()) {
        ImGui::SetNextWindowPos(centre, ImGuiCond_Always, {0.5f, 0.5f});
        ImGui::Begin("You win", nullptr, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::Text("All %d found in %.1f s.", int(game.collectibles().size()), game.time());
        ImGui::Text("They were only ever in the mirrors.");
        ImGui::Text("Esc quits.");
        ImGui::End();
    } else if (hud.paused) {
        ImGui::SetNextWindowPos(centre, ImGuiCond_Always, {0.5f, 0.5f});
        ImGui::Begin("Paused", nullptr, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::Text("Find the glowing gems: they show only in reflections.");
        ImGui::Text("Walk into one to take it. The timer stops when you have all.");
        ImGui::Separator();
        ImGui::Text("W A S D   walk");
        ImGui::Text("mouse     look");
        ImGui::Text("space     jump");
        ImGui::Text("Esc       this menu");
        ImGui::Separator();
        if (ImGui::Button("Resume")) hud.paused = false;
        ImGui::SameLine();
        if (ImGui::Button("Quit")) glfwSetWindowShouldClose(glfwGetCurrentContext(), GLFW_TRUE);
        ImGui::End();
    }
}

// The dynamic resolution: the scale moves by the square root of the frame-time ratio (pixels go
// with its square), in steps, so that the graph's images are not resized every frame.
float nextScale(float scale, double smoothedMs) {
    float wanted = scale * float(std::sqrt(kTargetMs / std::max(1.0, smoothedMs)));
    wanted = std::clamp(std::round(wanted / kScaleStep) * kScaleStep, kMinScale, 1.0f);
    return std::abs(wanted - scale) >= kScaleStep - 1e-4f ? wanted : scale;
}

GLFWwindow* gWindow = nullptr;
bool* gPaused = nullptr;

int run(Options opt) {
    game::Recording replay;
    bool replaying = !opt.replay.empty();
    if (replaying) {
        replay = game::readRecording(opt.replay);
        opt.scene = sceneFile(replay.scene);
        opt.size = std::to_string(replay.width) + "x" + std::to_string(replay.height);
        opt.preset = replay.preset;
    }
    auto [width, height] = app::parseSize(opt.size);
    if (!app::displayAvailable()) {
        std::cerr << "speculum-game: no display found (DISPLAY/WAYLAND_DISPLAY unset or unreachable); render "
                     "headless instead: build/engine/speculum-capture --scene "
                  << opt.scene << " --out out/\n";
        return 1;
    }
    Scene scene = loadScene(opt.scene);
    Settings settings(app::settingsOf({}, {probes::moduleInfo(), reflections::moduleInfo()}));
    loadPreset(settings, opt.preset);
    for (const std::string& kv : opt.sets) settings.assign(kv);
    game::Game game(scene);
    if (game.collectibles().empty())
        std::cout << "speculum-game: " << opt.scene << " has no collectible.N nodes: nothing to find\n";

    app::Window window("Speculum", width, height);
    gpu::Context ctx(gpu::ContextOptions{
        .deviceName = opt.device, .instanceExtensions = app::Window::requiredExtensions(), .swapchain = true});
    app::checkSceneFitsDevice(ctx, scene);
    render::Renderer renderer(ctx, scene);
    probes::Probes probeModule(ctx, renderer, probes::ProbeSettings::from(settings));
    reflections::Reflections module(ctx, renderer);
    app::Swapchain swapchain(ctx, window);

    Hud hud;
    hud.preset = int(std::find(std::begin(kPresets), std::end(kPresets), opt.preset) - std::begin(kPresets));
    gWindow = window.handle();
    gPaused = &hud.paused;
    // Before the UI layer: ImGui's GLFW backend chains the callbacks installed before it.
    glfwSetKeyCallback(window.handle(), [](GLFWwindow* w, int key, int, int action, int) {
        if (key != GLFW_KEY_ESCAPE || action != GLFW_PRESS) return;
        *gPaused = !*gPaused;
        glfwSetInputMode(w, GLFW_CURSOR, *gPaused ? GLFW_CURSOR_NORMAL : GLFW_CURSOR_DISABLED);
    });
    editor::UiLayer ui(ctx, window.handle(), swapchain.format(), swapchain.imageCount());
    if (!replaying) glfwSetInputMode(window.handle(), GLFW_CURSOR, GLFW_CURSOR_DISABLED);

    VkExtent2D extent = swapchain.extent();
    float scale = opt.scale > 0.0f ? opt.scale
                                   : std::clamp(float(std::sqrt(256.0 * 144.0 / (double(extent.width) * extent.height))),
                                                kMinScale, 1.0f);
    auto internalOf = [&](VkExtent2D e, float s) {
        return VkExtent2D{std::max(16u, uint32_t(std::lround(float(e.width) * s))),
                          std::max(16u, uint32_t(std::lround(float(e.height) * s)))};
    };
    VkExtent2D internal = internalOf(extent, scale);
    app::FrameRunner runner(ctx, renderer, internal.width, internal.height);

    game::Recording recording{std::filesystem::path(opt.scene).filename().string(), width, height, opt.preset, {}};
    double lastX = 0, lastY = 0;
    glfwGetCursorPos(window.handle(), &lastX, &lastY);
    render::FrameInputs frame;
    frame.primaryView = true;
    bool first = true;
    auto last = std::chrono::steady_clock::now();
    double fpsTime = 0.0, smoothedMs = 0.0;
    int fpsFrames = 0, frames = 0, sinceResize = 0;
    size_t cursor = 0;  // the recording's frame: one per loop, rendered or not (a swapchain re-creation)
    bool baked = true;
    std::vector<app::PassTime> lastPasses;
    while (!window.shouldClose() && (opt.frames <= 0 || frames < opt.frames)) {
        glfwPollEvents();
        auto now = std::chrono::steady_clock::now();
        double wallMs = std::chrono::duration<double, std::milli>(now - last).count();
        last = now;
        game::FrameInput in;
        if (replaying) {
            if (cursor >= replay.frames.size()) break;
            in = replay.frames[cursor++];
        } else {
            in = liveInput(window.handle(), !hud.paused && !game.won(), lastX, lastY);
            // A probe re-bake's frame is not a frame of play: the player does not jump ahead.
            in.dt = first || baked ? float(game::kStep) : float(std::min(wallMs, 100.0) / 1000.0);
            in.scale = scale;
            recording.frames.push_back(in);
        }
        game::Game::Events ev = game.advance(in, hud.paused);
        if (ev.hitWall)
            std::printf("frame %d: wall hit at (%.2f, %.2f)\n", frames, game.player().feet.x, game.player().feet.z);
        for (int i : ev.collected) {
            const game::Collectible& c = game.collectibles()[size_t(i)];
            std::printf("frame %d: collected %s (%d/%zu) at %.2f s\n", frames, c.name.c_str(), game.taken(),
                        game.collectibles().size(), game.time());
            // Gone from the main view and, after the re-bake, from every reflection.
            renderer.setNodeVisible(c.node, false);
            probeModule.requestUpdate(-1);
        }
        if (ev.won)
            std::printf("frame %d: won: all %zu found in %.2f s, %d wall hits\n", frames, game.collectibles().size(),
                        game.time(), game.wallHits());
        std::fflush(stdout);
        baked = !ev.collected.empty();
        if (reflections::probesInUse(settings))
            probeModule.update(frames == 0 ? probes::Probes::terminalProgress() : probes::Probes::Progress{});
        if (!swapchain.acquire()) continue;
        extent = swapchain.extent();
        VkExtent2D was = internal;
        internal = internalOf(extent, replaying ? in.scale : scale);
        if (internal.width != was.width || internal.height != was.height) {
            runner.resize(internal.width, internal.height);
            std::printf("frame %d: internal resolution %ux%u\n", frames, internal.width, internal.height);
            // Last frame's history has the old size: start the temporal accumulation afresh.
            module.resetHistory();
        }
        frame.previousCamera = frame.camera;
        frame.camera = render::makeCamera(game.eye(), game.eye() + game.forward(), {0, 1, 0}, glm::radians(70.0f),
                                          internal.width, internal.height);
        if (first) frame.previousCamera = frame.camera;
        first = false;

        ui.beginInput();
        ImGui::NewFrame();
        drawHud(hud, settings, game, extent, internal, replaying);
        ImGui::Render();
        std::vector<std::string> aovs;
        if (opt.shotFrames.count(frames)) aovs.push_back("color");
        app::FrameResult result = runner.render(
            frame, aovs, reflections::litHook(module, &probeModule, settings, frame),
            [&](FrameGraph& g, TextureHandle color) { addPresentPasses(g, color, swapchain, ui); },
            swapchain.acquired(), swapchain.rendered());
        swapchain.present();
        ui.endFrame();
        lastPasses = result.passes;
        if (!aovs.empty()) {
            char name[64];
            std::snprintf(name, sizeof name, "frame.%04d.png", frames);
            std::filesystem::create_directories(opt.shots);
            app::writePng(std::filesystem::path(opt.shots) / name, result.aovs.at("color"));
        }
        ++frames;
        if (opt.frames > 0 && (frames % 100 == 0 || frames == opt.frames))
            std::cout << "frame " << frames << ": rss " << residentMb() << " MB\n" << std::flush;
        // Dynamic resolution, from the wall time of whole frames (what the player feels).
        if (!replaying && opt.scale <= 0.0f && !baked && frames > 2) {
            smoothedMs = smoothedMs == 0.0 ? wallMs : 0.7 * smoothedMs + 0.3 * wallMs;
            if (++sinceResize >= 6) {
                float next = nextScale(scale, smoothedMs);
                if (next != scale) {
                    scale = next;
                    sinceResize = 0;
                    smoothedMs = 0.0;
                }
            }
        }
        fpsTime += wallMs / 1000.0;
        if (++fpsFrames >= 10 || fpsTime > 1.0) {
            hud.fps = fpsFrames / std::max(1e-6, fpsTime);
            hud.gpuMs = result.frameMs;
            std::printf("%.1f fps (GPU %.1f ms) at %ux%u, preset %s\n", hud.fps, hud.gpuMs, internal.width,
                        internal.height, kPresets[hud.preset]);
            std::fflush(stdout);
            fpsTime = 0.0;
            fpsFrames = 0;
        }
    }
    std::sort(lastPasses.begin(), lastPasses.end(), [](const auto& a, const auto& b) { return a.ms > b.ms; });
    std::printf("costliest passes of the last frame:");
    for (size_t i = 0; i < lastPasses.size() && i < 6; ++i) std::printf(" %s %.1f ms", lastPasses[i].name.c_str(), lastPasses[i].ms);
    std::printf("\n");
    if (!opt.record.empty()) {
        game::writeRecording(opt.record, recording);
        std::cout << "speculum-game: recorded " << recording.frames.size() << " frames to " << opt.record << "\n";
    }
    std::printf("speculum-game: %d frames, found %d/%zu, %s\n", frames, game.taken(), game.collectibles().size(),
                game.won() ? "won" : "not won");
    if (ctx.validationEnabled() && gpu::Context::validationMessageCount() > 0) {
        std::cerr << "speculum-game: " << gpu::Context::validationMessageCount() << " Vulkan validation messages\n";
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    std::string shotFrames;
    CLI::App cli{"speculum-game: find the gems that only the mirrors show (WASD walk, mouse look, space jumps, Esc pauses)"};
    cli.add_option("--scene", opt.scene, "glTF level (default: assets/scenes/hall_of_mirrors.gltf)");
    cli.add_option("--device", opt.device, "Vulkan device name (substring)");
    cli.add_option("--frames", opt.frames, "quit after N frames (0: run until quit)");
    cli.add_option("--size", opt.size, "window size WxH (default 1280x720)");
    cli.add_option("--preset", opt.preset, "quality preset: low, medium, high (assets/settings)");
    cli.add_option("--set", opt.sets, "KEY=VALUE: a setting over the preset (reflections.*, probes.*)");
    cli.add_option("--scale", opt.scale, "fixed internal resolution scale in [0.1, 1] (default: dynamic)");
    auto* rec = cli.add_option("--record", opt.record, "write the session's inputs and frame times to FILE");
    cli.add_option("--replay", opt.replay, "replay a recorded session (its scene, size and preset)")->excludes(rec);
    cli.add_option("--shots", opt.shots, "folder for --shot-frames images (the colour before the HUD)");
    cli.add_option("--shot-frames", shotFrames, "frame numbers to write, comma separated");
    try {
        cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return cli.exit(e) == 0 ? 0 : static_cast<int>(ExitCode::BadArguments);
    }
    try {
        if (opt.frames < 0) throw argumentError("--frames must be 0 (until quit) or more");
        if (opt.scale != 0.0f && !(opt.scale >= 0.1f && opt.scale <= 1.0f)) throw argumentError("--scale must be in [0.1, 1]");
        std::stringstream list(shotFrames);
        for (std::string item; std::getline(list, item, ',');) {
            try {
                opt.shotFrames.insert(std::stoi(item));
            } catch (const std::exception&) {
                throw argumentError("--shot-frames: '" + item + "' is not a frame number");
            }
        }
        if (!opt.shotFrames.empty() && opt.shots.empty()) throw argumentError("--shot-frames needs --shots DIR");
        return run(opt);
    } catch (const Error& e) {
        std::cerr << "speculum-game: " << e.what() << "\n";
        return static_cast<int>(e.code());
    } catch (const std::exception& e) {
        std::cerr << "speculum-game: internal error: " << e.what() << "\n";
        return 1;
    }
}
