// speculum-game: fly through a scene. WASD moves, the mouse (right button held, or always when
// the cursor is captured with Tab) looks around, Q/E go down/up, Shift is fast, Esc quits.
#include "speculum/app/device_budget.hpp"
#include "speculum/app/engine_settings.hpp"
#include "speculum/app/frame_runner.hpp"
#include "speculum/app/output.hpp"
#include "speculum/reflections/hook.hpp"
#include "speculum/app/window.hpp"
#include "speculum/core.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"

#include <CLI/CLI.hpp>
#include <GLFW/glfw3.h>

#include "speculum/app/camera_flags.hpp"

#include <chrono>
#include <fstream>
#include <unistd.h>
#include <cmath>
#include <iostream>

using namespace speculum;

namespace {

struct FlyCamera {
    glm::vec3 position{0.0f};
    float yaw = 0.0f;    // radians, 0 looks down -Z
    float pitch = 0.0f;  // radians
    glm::vec3 forward() const {
        return {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
    }
};

FlyCamera startCamera(const Scene& scene) {
    FlyCamera cam;
    const Camera* main = scene.cameras.empty() ? nullptr : &scene.cameras.front();
    glm::vec3 eye, dir;
    if (main) {
        eye = glm::vec3(main->world[3]);
        dir = -glm::normalize(glm::vec3(main->world[2]));
    } else {
        glm::vec3 c = 0.5f * (scene.boundsMin + scene.boundsMax);
        eye = c + glm::vec3(0.0f, 0.0f, glm::length(scene.boundsMax - scene.boundsMin));
        dir = glm::normalize(c - eye);
    }
    cam.position = eye;
    cam.yaw = std::atan2(-dir.x, -dir.z);
    cam.pitch = std::asin(glm::clamp(dir.y, -1.0f, 1.0f));
    return cam;
}

void updateCamera(GLFWwindow* w, FlyCamera& cam, float dt, double& lastX, double& lastY, float speed) {
    double x, y;
    glfwGetCursorPos(w, &x, &y);
    bool look = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                glfwGetInputMode(w, GLFW_CURSOR) == GLFW_CURSOR_DISABLED;
    if (look) {
        cam.yaw -= float(x - lastX) * 0.003f;
        cam.pitch = glm::clamp(cam.pitch - float(y - lastY) * 0.003f, -1.5f, 1.5f);
    }
    lastX = x;
    lastY = y;
    glm::vec3 f = cam.forward();
    glm::vec3 r = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
    glm::vec3 move(0.0f);
    if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS) move += f;
    if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS) move -= f;
    if (glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS) move += r;
    if (glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS) move -= r;
    if (glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS) move.y += 1.0f;
    if (glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS) move.y -= 1.0f;
    float boost = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 4.0f : 1.0f;
    if (glm::length(move) > 0.0f) cam.position += glm::normalize(move) * speed * boost * dt;
}

// Resident set size now, from /proc/self/statm (pages), in MB; 0 where there is no /proc.
double residentMb() {
    std::ifstream statm("/proc/self/statm");
    unsigned long long size = 0, resident = 0;
    if (!(statm >> size >> resident)) return 0.0;
    return double(resident) * double(sysconf(_SC_PAGESIZE)) / 1048576.0;
}

int run(const std::string& scenePath, const std::string& device, int maxFrames, uint32_t width, uint32_t height) {
    if (!app::displayAvailable()) {
        std::cerr << "speculum-game: no display found (DISPLAY/WAYLAND_DISPLAY unset or unreachable); render "
                     "headless instead: build/engine/speculum-capture --scene "
                  << scenePath << " --out out/\n";
        return 1;
    }
    Scene scene = loadScene(scenePath);
    app::Window window("Speculum", width, height);
    gpu::Context ctx(gpu::ContextOptions{
        .deviceName = device, .instanceExtensions = app::Window::requiredExtensions(), .swapchain = true});
    app::checkSceneFitsDevice(ctx, scene);
    render::Renderer renderer(ctx, scene);
    // The sample plays with the module's defaults; the editor is where settings change.
    Settings settings(app::settingsOf({}, {probes::moduleInfo(), reflections::moduleInfo()}));
    probes::Probes probeModule(ctx, renderer);
    reflections::Reflections module(ctx, renderer);
    app::Swapchain swapchain(ctx, window);
    app::FrameRunner runner(ctx, renderer, swapchain.extent().width, swapchain.extent().height);

    FlyCamera cam = startCamera(scene);
    float speed = std::max(1.0f, 0.25f * glm::length(scene.boundsMax - scene.boundsMin));
    double lastX = 0, lastY = 0;
    glfwGetCursorPos(window.handle(), &lastX, &lastY);
    render::FrameInputs frame;
    bool first = true;
    auto last = std::chrono::steady_clock::now();
    double fpsTime = 0.0;
    int fpsFrames = 0, frames = 0;
    glfwSetKeyCallback(window.handle(), [](GLFWwindow* w, int key, int, int action, int) {
        if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
        if (key == GLFW_KEY_TAB && action == GLFW_PRESS)
            glfwSetInputMode(w, GLFW_CURSOR,
                             glfwGetInputMode(w, GLFW_CURSOR) == GLFW_CURSOR_DISABLED ? GLFW_CURSOR_NORMAL
                                                                                      : GLFW_CURSOR_DISABLED);
    });
    while (!window.shouldClose() && (maxFrames <= 0 || frames < maxFrames)) {
        glfwPollEvents();
        auto now = std::chrono::steady_clock::now();
        float dt = std::chrono::duration<float>(now - last).count();
        last = now;
        updateCamera(window.handle(), cam, dt, lastX, lastY, speed);
        // Probe captures are graphs of their own: before the frame's graph, outside the swapchain.
        if (reflections::probesInUse(settings))
            probeModule.update(frames == 0 ? probes::Probes::terminalProgress() : probes::Probes::Progress{});
        if (!swapchain.acquire()) continue;
        VkExtent2D e = swapchain.extent();
        runner.resize(e.width, e.height);
        frame.previousCamera = frame.camera;
        frame.camera = render::makeCamera(cam.position, cam.position + cam.forward(), {0, 1, 0}, glm::radians(60.0f),
                                          e.width, e.height);
        if (first) frame.previousCamera = frame.camera;
        first = false;
        app::FrameResult result = runner.render(
            frame, {}, reflections::litHook(module, &probeModule, settings, frame),
            [&](FrameGraph& g, TextureHandle color) { swapchain.addPresentPass(g, color); },
            swapchain.acquired(), swapchain.rendered());
        swapchain.present();
        ++frames;
        // With --frames, a memory line every 100 frames: the soak test's evidence (issue 15).
        if (maxFrames > 0 && (frames % 100 == 0 || frames == maxFrames))
            std::cout << "frame " << frames << ": rss " << residentMb() << " MB\n" << std::flush;
        fpsTime += dt;
        if (++fpsFrames >= 10 || fpsTime > 1.0) {
            char title[160];
            std::snprintf(title, sizeof title, "Speculum - %.1f fps (GPU %.1f ms) - WASD/QE move, right mouse looks, Esc quits",
                          fpsFrames / fpsTime, result.frameMs);
            window.setTitle(title);
            std::cout << title + 11 << "\n" << std::flush;
            fpsTime = 0.0;
            fpsFrames = 0;
        }
    }
    if (ctx.validationEnabled() && gpu::Context::validationMessageCount() > 0) {
        std::cerr << "speculum-game: " << gpu::Context::validationMessageCount() << " Vulkan validation messages\n";
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene = std::string(SPECULUM_SOURCE_DIR) + "/assets/scenes/gallery.gltf";
    std::string device;
    int frames = 0;
    std::string size = "1280x720";
    CLI::App cli{"speculum-game: fly through a scene (WASD, Q/E, right mouse, Tab captures the mouse, Esc quits)"};
    cli.add_option("--scene", scene, "glTF scene (default: the gallery)");
    cli.add_option("--device", device, "Vulkan device name (substring)");
    cli.add_option("--frames", frames, "quit after N frames (0: run until Esc)");
    cli.add_option("--size", size, "window size WxH (default 1280x720)");
    try {
        cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return cli.exit(e) == 0 ? 0 : static_cast<int>(ExitCode::BadArguments);
    }
    try {
        if (frames < 0) throw argumentError("--frames must be 0 (until Esc) or more");
        auto [w, h] = app::parseSize(size);
        return run(scene, device, frames, w, h);
    } catch (const Error& e) {
        std::cerr << "speculum-game: " << e.what() << "\n";
        return static_cast<int>(e.code());
    } catch (const std::exception& e) {
        std::cerr << "speculum-game: internal error: " << e.what() << "\n";
        return 1;
    }
}
