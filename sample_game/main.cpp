// speculum-game: walk the hall of mirrors and find the collectibles, which only the mirrors show
// (sample_game/README.md: controls, recordings, frame rates). The HUD (Dear ImGui through the
// engine's UI layer, the game.hud pass) shows fps and GPU time and toggles each reflection
// method; the internal resolution follows the frame time and the image is upscaled to the window.
#include "game.hpp"

#include "speculum/app/device_budget.hpp"
#include "speculum/app/camera_flags.hpp"
#include "speculum/app/frame_runner.hpp"
#include "speculum/app/output.hpp"
#include "speculum/app/tool_main.hpp"
#include "speculum/app/window.hpp"
#include "speculum/chain.hpp"
#include "speculum/core.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"
#include "speculum/ui/ui_layer.hpp"

#include <CLI/CLI.hpp>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
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
void addPresentPasses(FrameGraph& g, TextureHandle color, app::Swapchain& swapchain, ui::UiLayer& ui) {
    ui.addPass(g, swapchain.addPresentPass(g, color, VK_FILTER_LINEAR), "game.hud");
}

struct Hud {
    double fps = 0.0, gpuMs = 0.0;
    int preset = 0;
    bool paused = false;
    std::vector<std::string> changes;  // this frame's settings changes, for the recording
};

GLFWwindow* gWindow = nullptr;

// A setting change from the HUD or a recording ("preset=NAME" loads a preset).
void applySetting(Settings& settings, Hud& hud, const std::string& kv) {
    if (kv.rfind("preset=", 0) == 0) {
        std::string name = kv.substr(7);
        loadPreset(settings, name);
        hud.preset = int(std::find(std::begin(kPresets), std::end(kPresets), name) - std::begin(kPresets));
    } else {
        settings.assign(kv);
    }
    hud.changes.push_back(kv);
}

void checkbox(Settings& settings, Hud& hud, const char* label, const std::string& name) {
    bool v = settings.getBool(name);
    if (ImGui::Checkbox(label, &v)) applySetting(settings, hud, name + (v ? "=true" : "=false"));
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
    if (ImGui::Combo("preset", &hud.preset, kPresets, 3))
        applySetting(settings, hud, std::string("preset=") + kPresets[hud.preset]);
    checkbox(settings, hud, "screen space", "reflections.screen_space");
    ImGui::SameLine();
    checkbox(settings, hud, "CMOs", "reflections.cmos");
    ImGui::SameLine();
    checkbox(settings, hud, "probes", "reflections.probes");
    ImGui::SameLine();
    checkbox(settings, hud, "temporal", "reflections.temporal");
    // Every hosted module's debug views (reflections.debug_view, probes.debug_view).
    for (const SettingDesc& dv : settings.table()) {
        const std::string suffix = ".debug_view";
        if (dv.type != SettingType::Enum || dv.name.size() < suffix.size() ||
            dv.name.compare(dv.name.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        int view = settings.getInt(dv.name);
        std::vector<const char*> names;
        for (const std::string& c : dv.choices) names.push_back(c.c_str());
        if (ImGui::Combo(dv.name.c_str(), &view, names.data(), int(names.size())))
            applySetting(settings, hud, dv.name + "=" + dv.choices[size_t(view)]);
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
        if (ImGui::Button("Quit")) glfwSetWindowShouldClose(gWindow, GLFW_TRUE);
        ImGui::End();
    }
}


// The game's window, device, modules and state; one frame() per loop.
class GameApp {
public:
    explicit GameApp(Options opt);
    // One loop: input, simulation, probe updates, render, dynamic resolution. False: done.
    bool frame();
    // The recording, the summary and the validation verdict: the exit status.
    int finish();

private:
    game::FrameInput nextInput(double wallMs, bool& done);
    void apply(const game::Game::Events& ev);
    void render(const game::FrameInput& in);
    void adaptScale(double wallMs);
    VkExtent2D internalOf(VkExtent2D e, float s) const {
        return {std::max(16u, uint32_t(std::lround(float(e.width) * s))),
                std::max(16u, uint32_t(std::lround(float(e.height) * s)))};
    }

    game::Recording replay_;  // before opt_: withReplay() fills it while opt_ is initialised
    Options opt_;
    bool replaying_;
    Scene scene_;
    Settings settings_;
    game::Game game_;
    app::Window window_;
    gpu::Context ctx_;
    render::Renderer renderer_;
    chain::Chain chain_;  // probes, then reflections
    app::Swapchain swapchain_;
    Hud hud_;
    std::unique_ptr<ui::UiLayer> ui_;
    float scale_ = 1.0f;
    VkExtent2D internal_{};
    std::unique_ptr<app::FrameRunner> runner_;
    game::Recording recording_;
    double lastX_ = 0, lastY_ = 0;
    render::FrameInputs frame_;
    bool first_ = true, baked_ = true;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    double fpsTime_ = 0.0, smoothedMs_ = 0.0;
    double presentMs_ = 0.0;  // in vkQueuePresentKHR since the last fps line
    double eventsMs_ = 0.0;   // in glfwPollEvents since the last fps line
    int fpsFrames_ = 0, frames_ = 0, sinceResize_ = 0;
    double worstMs_ = 0.0;  // the slowest frame after the start's bake, and which it was
    int worstFrame_ = -1;
    double hitchBaseMs_ = 0.0;  // the running (smoothed) frame time a hitch is measured against
    size_t cursor_ = 0;  // the recording's frame: one per loop, rendered or not (a swapchain re-creation)
    std::vector<app::PassTime> lastPasses_;
};

bool* gPaused = nullptr;
const game::Game* gGame = nullptr;

// Everything a replay fixes comes from the recording before anything opens.
Options withReplay(Options opt, game::Recording& replay) {
    if (opt.replay.empty()) return opt;
    replay = game::readRecording(opt.replay);
    opt.scene = sceneFile(replay.scene);
    opt.size = std::to_string(replay.width) + "x" + std::to_string(replay.height);
    opt.preset = replay.preset;
    return opt;
}

Settings presetSettings(const Options& opt) {
    Settings settings(app::settingsOf({}, chain::moduleInfos()));
    loadPreset(settings, opt.preset);
    for (const std::string& kv : opt.sets) settings.assign(kv);
    return settings;
}

gpu::ContextOptions contextOptions(const Options& opt) {
    return {.deviceName = opt.device, .instanceExtensions = app::Window::requiredExtensions(), .swapchain = true};
}

// The context, once the scene's buffers are known to fit its memory.
const gpu::Context& fitted(const gpu::Context& ctx, const Scene& scene) {
    app::checkSceneFitsDevice(ctx, scene);
    return ctx;
}

uint32_t widthOf(const Options& opt) { return app::parseSize(opt.size).first; }
uint32_t heightOf(const Options& opt) { return app::parseSize(opt.size).second; }

GameApp::GameApp(Options opt)
    : replay_(),
      opt_(withReplay(std::move(opt), replay_)),
      replaying_(!opt_.replay.empty()),
      scene_(loadScene(opt_.scene)),
      settings_(presetSettings(opt_)),
      game_(scene_),
      window_("Speculum", widthOf(opt_), heightOf(opt_)),
      ctx_(contextOptions(opt_)),
      renderer_(fitted(ctx_, scene_), scene_),
      chain_(ctx_, renderer_, settings_),
      swapchain_(ctx_, window_) {
    if (game_.collectibles().empty())
        std::cout << "speculum-game: " << opt_.scene << " has no collectible.N nodes: nothing to find\n";
    hud_.preset = int(std::find(std::begin(kPresets), std::end(kPresets), opt_.preset) - std::begin(kPresets));
    gPaused = &hud_.paused;
    gGame = &game_;
    gWindow = window_.handle();
    // Before the UI layer: ImGui's GLFW backend chains the callbacks installed before it.
    glfwSetKeyCallback(window_.handle(), [](GLFWwindow* w, int key, int, int action, int) {
        if (key != GLFW_KEY_ESCAPE || action != GLFW_PRESS) return;
        if (gGame->won()) {
            glfwSetWindowShouldClose(w, GLFW_TRUE);
            return;
        }
        *gPaused = !*gPaused;
        std::printf("%s\n", *gPaused ? "paused" : "resumed");
        glfwSetInputMode(w, GLFW_CURSOR, *gPaused ? GLFW_CURSOR_NORMAL : GLFW_CURSOR_DISABLED);
    });
    ui_ = std::make_unique<ui::UiLayer>(ctx_, window_.handle(), swapchain_.format(), swapchain_.imageCount());
    if (!replaying_) glfwSetInputMode(window_.handle(), GLFW_CURSOR, GLFW_CURSOR_DISABLED);
    VkExtent2D extent = swapchain_.extent();
    scale_ = opt_.scale > 0.0f ? opt_.scale
                               : std::clamp(float(std::sqrt(256.0 * 144.0 / (double(extent.width) * extent.height))),
                                            kMinScale, 1.0f);
    internal_ = internalOf(extent, scale_);
    runner_ = std::make_unique<app::FrameRunner>(ctx_, renderer_, internal_.width, internal_.height);
    recording_ = {std::filesystem::path(opt_.scene).filename().string(), widthOf(opt_), heightOf(opt_), opt_.preset, {}};
    glfwGetCursorPos(window_.handle(), &lastX_, &lastY_);
    frame_.primaryView = true;
}

game::FrameInput GameApp::nextInput(double wallMs, bool& done) {
    game::FrameInput in;
    if (replaying_) {
        done = cursor_ >= replay_.frames.size();
        return done ? in : replay_.frames[cursor_++];
    }
    in = liveInput(window_.handle(), !hud_.paused && !game_.won(), lastX_, lastY_);
    // A probe re-bake's frame is not a frame of play: the player does not jump ahead.
    in.dt = first_ || baked_ ? float(game::kStep) : float(std::min(wallMs, 100.0) / 1000.0);
    in.scale = scale_;
    recording_.frames.push_back(in);
    return in;
}

void GameApp::apply(const game::Game::Events& ev) {
    if (ev.hitWall)
        std::printf("frame %d: wall hit at (%.2f, %.2f)\n", frames_, game_.player().feet.x, game_.player().feet.z);
    for (int i : ev.collected) {
        const game::Collectible& c = game_.collectibles()[size_t(i)];
        std::printf("frame %d: collected %s (%d/%zu) at %.2f s\n", frames_, c.name.c_str(), game_.taken(),
                    game_.collectibles().size(), game_.time());
        // Gone from the main view at once and from the reflections as the probe and the CMOs
        // are captured again, a face per frame (a whole re-bake here made 390-400 ms frames at 320x180).
        renderer_.setNodeVisible(c.node, false);
        chain_.probes().recapture(-1);
    }
    if (ev.won)
        std::printf("frame %d: won: all %zu found in %.2f s, %d wall hits\n", frames_, game_.collectibles().size(),
                    game_.time(), game_.wallHits());
    std::fflush(stdout);
    baked_ = !ev.collected.empty();
}

bool GameApp::frame() {
    if (window_.shouldClose() || (opt_.frames > 0 && frames_ >= opt_.frames)) return false;
    // Under Xvfb this waits for the X server to finish reading the last present's image (GLFW's
    // X11 backend makes a round trip here while the cursor is disabled): 6-9 ms a frame at
    // 1280x720 (README, measured frame rates), so the fps line shows it beside the present.
    auto eventsStart = std::chrono::steady_clock::now();
    glfwPollEvents();
    auto now = std::chrono::steady_clock::now();
    eventsMs_ += std::chrono::duration<double, std::milli>(now - eventsStart).count();
    double wallMs = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    // wallMs is the frame before this one; the first frames bake the probes and compile.
    if (frames_ > 3) {
        if (wallMs > worstMs_) {
            worstMs_ = wallMs;
            worstFrame_ = frames_ - 1;
        }
        // A hitch: over 100 ms and over twice the running frame time (a bake, a pipeline compiled).
        if (wallMs > 100.0 && wallMs > 2.0 * hitchBaseMs_)
            std::printf("frame %d: hitch, %.0f ms (frames take about %.0f ms)\n", frames_ - 1, wallMs, hitchBaseMs_);
    }
    hitchBaseMs_ = hitchBaseMs_ == 0.0 ? wallMs : 0.9 * hitchBaseMs_ + 0.1 * wallMs;
    bool done = false;
    game::FrameInput in = nextInput(wallMs, done);
    if (done) return false;
    apply(game_.advance(in, hud_.paused));
    chain_.update(settings_, frames_ == 0 ? probes::Probes::terminalProgress() : probes::Probes::Progress{});
    if (!swapchain_.acquire()) return true;
    render(in);
    ++frames_;
    if (opt_.frames > 0 && (frames_ % 100 == 0 || frames_ == opt_.frames))
        std::cout << "frame " << frames_ << ": rss " << residentMb() << " MB\n" << std::flush;
    adaptScale(wallMs);
    fpsTime_ += wallMs / 1000.0;
    if (++fpsFrames_ >= 10 || fpsTime_ > 1.0) {
        hud_.fps = fpsFrames_ / std::max(1e-6, fpsTime_);
        std::printf("%.1f fps (GPU %.1f ms, present %.1f ms, events %.1f ms) at %ux%u, preset %s\n", hud_.fps,
                    hud_.gpuMs, presentMs_ / fpsFrames_, eventsMs_ / fpsFrames_, internal_.width, internal_.height,
                    kPresets[hud_.preset]);
        std::fflush(stdout);
        fpsTime_ = 0.0;
        fpsFrames_ = 0;
        presentMs_ = 0.0;
        eventsMs_ = 0.0;
    }
    return true;
}

void GameApp::render(const game::FrameInput& in) {
    VkExtent2D extent = swapchain_.extent(), was = internal_;
    internal_ = internalOf(extent, replaying_ ? in.scale : scale_);
    if (internal_.width != was.width || internal_.height != was.height) {
        runner_->resize(internal_.width, internal_.height);
        std::printf("frame %d: internal resolution %ux%u\n", frames_, internal_.width, internal_.height);
        // Last frame's history has the old size: start the temporal accumulation afresh.
        chain_.resetHistory();
    }
    frame_.previousCamera = frame_.camera;
    frame_.camera = render::makeCamera(game_.eye(), game_.eye() + game_.forward(), {0, 1, 0}, glm::radians(70.0f),
                                       internal_.width, internal_.height);
    if (first_) frame_.previousCamera = frame_.camera;
    first_ = false;
    // A replay's recorded HUD changes apply where the player made them: before this frame renders.
    hud_.changes.clear();
    for (const std::string& kv : in.sets) applySetting(settings_, hud_, kv);
    ui_->beginInput();
    ImGui::NewFrame();
    drawHud(hud_, settings_, game_, extent, internal_, replaying_);
    ImGui::Render();
    for (const std::string& kv : hud_.changes) std::printf("frame %d: set %s\n", frames_, kv.c_str());
    if (!replaying_ && !recording_.frames.empty())
        // Live input carries no sets: every change here is the HUD's.
        for (const std::string& kv : hud_.changes) recording_.frames.back().sets.push_back(kv);
    std::vector<std::string> aovs;
    if (opt_.shotFrames.count(frames_)) aovs.push_back("color");
    app::FrameResult result = runner_->render(
        frame_, aovs, chain_.litHook(settings_, frame_),
        [&](FrameGraph& g, TextureHandle color) { addPresentPasses(g, color, swapchain_, *ui_); },
        swapchain_.acquired(), swapchain_.rendered());
    // The window system's share of the frame, outside the GPU timestamps: under Xvfb on lavapipe
    // (Mesa 22.3's software present copies the 1280x720 image to the X server with
    // xcb_put_image) 12-18 ms of a 70-85 ms frame at 480x270 (README, measured frame rates).
    auto presentStart = std::chrono::steady_clock::now();
    swapchain_.present();
    presentMs_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - presentStart).count();
    ui_->endFrame();
    lastPasses_ = result.passes;
    hud_.gpuMs = result.frameMs;
    if (!aovs.empty()) {
        char name[64];
        std::snprintf(name, sizeof name, "frame.%04d.png", frames_);
        std::filesystem::create_directories(opt_.shots);
        app::writePng(std::filesystem::path(opt_.shots) / name, result.aovs.at("color"));
    }
}

// Dynamic resolution, from the wall time of whole frames (what the player feels).
void GameApp::adaptScale(double wallMs) {
    if (replaying_ || opt_.scale > 0.0f || baked_ || frames_ <= 2) return;
    smoothedMs_ = smoothedMs_ == 0.0 ? wallMs : 0.7 * smoothedMs_ + 0.3 * wallMs;
    if (++sinceResize_ < 6) return;
    float next = game::nextScale(scale_, smoothedMs_, kTargetMs, kMinScale, kScaleStep);
    if (next == scale_) return;
    scale_ = next;
    sinceResize_ = 0;
    smoothedMs_ = 0.0;
}

int GameApp::finish() {
    std::sort(lastPasses_.begin(), lastPasses_.end(), [](const auto& a, const auto& b) { return a.ms > b.ms; });
    std::printf("costliest passes of the last frame:");
    for (size_t i = 0; i < lastPasses_.size() && i < 6; ++i)
        std::printf(" %s %.1f ms", lastPasses_[i].name.c_str(), lastPasses_[i].ms);
    std::printf("\n");
    if (!opt_.record.empty()) {
        game::writeRecording(opt_.record, recording_);
        std::cout << "speculum-game: recorded " << recording_.frames.size() << " frames to " << opt_.record << "\n";
    }
    if (worstFrame_ >= 0) std::printf("slowest frame after the start: %.1f ms (frame %d)\n", worstMs_, worstFrame_);
    std::printf("speculum-game: %d frames, found %d/%zu, %s\n", frames_, game_.taken(), game_.collectibles().size(),
                game_.won() ? "won" : "not won");
    if (ctx_.validationEnabled() && gpu::Context::validationMessageCount() > 0) {
        std::cerr << "speculum-game: " << gpu::Context::validationMessageCount() << " Vulkan validation messages\n";
        return 1;
    }
    return 0;
}

int run(const Options& opt) {
    // The recording names the scene; the display check comes before anything loads.
    game::Recording probe;
    Options resolved = opt.replay.empty() ? opt : withReplay(opt, probe);
    app::parseSize(resolved.size);
    if (!app::displayAvailable()) {
        std::cerr << "speculum-game: no display found (DISPLAY/WAYLAND_DISPLAY unset or unreachable); render "
                     "headless instead: build/tools/capture/speculum-capture --scene "
                  << resolved.scene << " --out out/\n";
        return 1;
    }
    GameApp app(opt);
    while (app.frame()) {
    }
    return app.finish();
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
    return app::toolMain("speculum-game", cli, argc, argv, [&] {
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
        if (std::find(std::begin(kPresets), std::end(kPresets), opt.preset) == std::end(kPresets))
            throw argumentError("--preset " + opt.preset + ": expected low, medium or high");
        return run(opt);
    });
}
