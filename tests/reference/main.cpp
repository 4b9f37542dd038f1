// speculum-reference: ground-truth renders of a glTF scene (docs/design.md sections 6 and 7).
// Takes speculum-capture's scene and camera flags and writes the same file names
// (NAME.FFFF.exr, color.FFFF.png) plus reference.json (time and rays per frame).
// Exit 0 done, 2 bad arguments, 3 bad scene or settings file.
#include "reference.hpp"

#include "speculum/app/camera_flags.hpp"
#include "speculum/app/engine_settings.hpp"
#include "speculum/app/output.hpp"
#include "speculum/app/camera_options.hpp"
#include "speculum/app/tool_main.hpp"
#include "speculum/core.hpp"
#include "speculum/limits.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace speculum;

namespace {

const std::vector<std::string> kAovs = {"linear", "color", "reflection", "depth", "normal", "reflective"};

struct Options {
    app::CameraFlags view;  // --scene, --camera, --eye, --target, --up, --fov, --path
    std::string size = "960x540", settingsFile, out;
    std::string aov = "linear,color,reflection,reflective";
    uint32_t spp = 64, bounces = 2, threads = 0;
    uint64_t seed = 1;
    std::vector<std::string> sets;
    bool settingsGiven = false;
};

// The reference flattens every primitive of every instance into world-space Embree meshes (no
// instancing), so a small file that places one big mesh many times costs memory per placement:
// one took 16.9 GB (issue 15). Per flattened vertex: the shading copy (position, normal, tangent,
// uv: 48 bytes) and Embree's float3 buffer (16); per triangle: 12 bytes of indices and about 128
// of a high-quality BVH with spatial splits. Refused past half of the machine's memory.
void checkReferenceBudget(const Scene& scene) {
    uint64_t vertices = 0, triangles = 0;
    for (const Instance& inst : scene.instances) {
        if (inst.mesh < 0 || size_t(inst.mesh) >= scene.meshes.size()) continue;
        for (const Primitive& p : scene.meshes[size_t(inst.mesh)].primitives) {
            vertices += p.vertices.size();
            triangles += p.indices.size() / 3;
        }
    }
    uint64_t need = vertices * 64 + triangles * 140;
    uint64_t memory = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
    if (need > memory / 2)
        throw inputError(scene.path.string(),
                         "the reference renderer would need about " + limits::bytesText(need) + " for " +
                             std::to_string(triangles) + " triangles over " + std::to_string(scene.instances.size()) +
                             " placed meshes, more than half of this machine's " + limits::bytesText(memory));
}

// speculum-capture's size rule plus a cap: the reference allocates per-pixel buffers up front.
std::pair<uint32_t, uint32_t> parseSize(const std::string& s) {
    auto [w, h] = app::parseSize(s);
    if (w > 16384 || h > 16384) throw argumentError("--size " + s + " is larger than 16384 pixels on a side");
    return {w, h};
}

std::vector<std::string> parseAovs(const std::string& list) {
    auto aovs = app::splitList(list);
    if (aovs.empty()) throw argumentError("--aov needs at least one of: linear, color, reflection, depth, normal, reflective");
    for (const std::string& a : aovs)
        if (std::find(kAovs.begin(), kAovs.end(), a) == kAovs.end())
            throw argumentError("unknown AOV '" + a + "' (known: linear, color, reflection, depth, normal, reflective)");
    return aovs;
}

app::AovImage toAov(const reference::Frame& f, const std::string& name, float exposure) {
    app::AovImage img{f.width, f.height, 3, std::vector<float>(size_t(f.width) * f.height * 4, 1.0f)};
    for (size_t i = 0; i < size_t(f.width) * f.height; ++i) {
        glm::vec3 v(0.0f);
        if (name == "linear") v = f.linear[i];
        else if (name == "color") v = reference::tonemap(f.linear[i], exposure);
        else if (name == "reflection") v = f.reflection[i];
        else if (name == "normal") v = f.normal[i];
        else v = glm::vec3(name == "depth" ? f.depth[i] : f.reflective[i]);
        for (int c = 0; c < 3; ++c) img.rgba[i * 4 + size_t(c)] = v[c];
    }
    if (name == "depth" || name == "reflective") img.channels = 1;
    return img;
}

// A bar that redraws in place on a terminal; nothing when stderr is a file (logs stay short).
void progressBar(size_t frame, size_t frames, uint32_t done, uint32_t total,
                 std::chrono::steady_clock::time_point start) {
    static const bool tty = isatty(2);
    if (!tty) return;
    const int width = 30;
    int filled = int(double(done) / total * width);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "\rreference frame %zu/%zu [%s%s] %3d%% %.1f s", frame + 1, frames,
                 std::string(size_t(filled), '#').c_str(), std::string(size_t(width - filled), '-').c_str(),
                 int(100.0 * done / total), seconds);
    if (done == total) std::fprintf(stderr, "\n");
}

int run(const Options& o) {
    if (o.out.empty()) throw argumentError("--out DIR is required");
    if (o.view.scenePath.empty()) throw argumentError("--scene FILE is required");
    if (o.spp < 1 || o.spp > 1u << 20) throw argumentError("--spp must be in 1..1048576");
    if (o.bounces < 1 || o.bounces > 64) throw argumentError("--bounces must be in 1..64");
    if (o.settingsGiven && o.settingsFile.empty()) throw argumentError("--settings needs a file name, got \"\"");
    auto [w, h] = parseSize(o.size);
    std::vector<std::string> aovs = parseAovs(o.aov);

    Settings settings(app::engineSettingsTable());
    if (o.settingsGiven) settings.load(o.settingsFile);
    for (const std::string& kv : o.sets) settings.assign(kv);
    render::RendererOptions ro = fromSettings<render::RendererOptions>(settings);

    auto setupStart = std::chrono::steady_clock::now();
    Scene scene = loadScene(o.view.scenePath);
    std::vector<render::CameraState> views =
        app::selectCameras(o.view, scene, w, h, 1);
    app::prepareOutputDir(o.out);  // before the BVH build and the sky prefilter
    checkReferenceBudget(scene);
    reference::Options ropt{o.spp, o.bounces, o.seed, o.threads, ro.exposure, {}};
    size_t frameIndex = 0;
    auto frameStart = std::chrono::steady_clock::now();
    ropt.progress = [&](uint32_t done, uint32_t total) { progressBar(frameIndex, views.size(), done, total, frameStart); };
    reference::Renderer renderer(scene, ropt);
    double setupSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();

    nlohmann::json frames = nlohmann::json::array();
    for (frameIndex = 0; frameIndex < views.size(); ++frameIndex) {
        frameStart = std::chrono::steady_clock::now();
        reference::Frame f = renderer.render(views[frameIndex]);
        for (const std::string& a : aovs) app::writeAov(o.out, a, int(frameIndex), toAov(f, a, renderer.exposure()));
        double raysPerSecond = f.rays / std::max(f.seconds, 1e-9);
        frames.push_back({{"frame", frameIndex}, {"seconds", f.seconds}, {"rays", f.rays},
                          {"rays_per_second", raysPerSecond}});
        std::printf("reference frame %zu: %.2f s, %.2f Mrays, %.2f Mrays/s\n", frameIndex, f.seconds, f.rays / 1e6,
                    raysPerSecond / 1e6);
    }
    nlohmann::json report = {{"scene", o.view.scenePath},         {"width", w},
                             {"height", h},              {"spp", o.spp},
                             {"bounces", o.bounces},     {"seed", o.seed},
                             {"threads", o.threads},     {"exposure", renderer.exposure()},
                             {"setup_seconds", setupSeconds}, {"frames", frames}};
    app::writeText(fs::path(o.out) / "reference.json", report.dump(2));
    std::fflush(stdout);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App cli{"speculum-reference: ground-truth Embree renders of a glTF scene, as speculum-capture frames it"};
    app::addCameraOptions(cli, o.view, o.size);
    cli.add_option("--spp", o.spp, "glossy reflection samples per pixel (default 64)");
    cli.add_option("--bounces", o.bounces, "reflective surfaces traced this deep (default 2)");
    cli.add_option("--seed", o.seed, "random seed (same seed, same image; default 1)");
    cli.add_option("--threads", o.threads, "render threads (default: all hardware threads)");
    app::addSettingsOptions(cli, o.settingsFile, o.sets, "render.exposure");
    cli.add_option("--aov", o.aov,
                   "comma list: linear,color,reflection,depth,normal,reflective (default linear,color,reflection,reflective)");
    cli.add_option("--out", o.out, "output directory");
    return app::toolMain("speculum-reference", cli, argc, argv, [&] {
        o.settingsGiven = cli.count("--settings") > 0;
        return run(o);
    });
}
