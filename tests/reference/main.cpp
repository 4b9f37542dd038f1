// speculum-reference: ground-truth renders of a glTF scene (docs/design.md sections 6 and 7).
// Takes speculum-capture's scene and camera flags and writes the same file names
// (NAME.FFFF.exr, color.FFFF.png) plus reference.json (time and rays per frame).
// Exit 0 done, 2 bad arguments, 3 bad scene or settings file.
#include "reference.hpp"
#include "metrics.hpp"

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

const std::vector<std::string> kAovs = {"linear", "color", "reflection", "depth", "normal", "reflective", "roughness", "samples", "stderror"};

struct Options {
    app::CameraFlags view;  // --scene, --camera, --eye, --target, --up, --fov, --path
    std::string size = "960x540", settingsFile, out;
    std::string aov = "linear,color,reflection,reflective";
    reference::Options render;  // the renderer's options as the flags give them (exposure from --set)
    uint32_t seeds = 1;
    float maxReferenceError = metrics::kMaxReferenceError;  // the seed agreement's cut, written to reference.json
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
    if (aovs.empty()) throw argumentError("--aov needs at least one of: linear, color, reflection, depth, normal, reflective, roughness, samples, stderror");
    for (const std::string& a : aovs)
        if (std::find(kAovs.begin(), kAovs.end(), a) == kAovs.end())
            throw argumentError("unknown AOV '" + a + "' (known: linear, color, reflection, depth, normal, reflective, roughness, samples, stderror)");
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
        else if (name == "roughness") v = glm::vec3(f.roughness[i]);
        else if (name == "samples") v = glm::vec3(f.samples[i]);
        else if (name == "stderror") v = glm::vec3(f.stderror[i]);
        else v = glm::vec3(name == "depth" ? f.depth[i] : f.reflective[i]);
        for (int c = 0; c < 3; ++c) img.rgba[i * 4 + size_t(c)] = v[c];
    }
    if (name == "depth" || name == "reflective" || name == "roughness" || name == "samples" || name == "stderror") img.channels = 1;
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

// Lobe samples over the reflective pixels: what adaptive sampling spent, and how many pixels
// ended above the target error (at their cap).
nlohmann::json sampleStats(const reference::Frame& f, float targetError) {
    double sum = 0.0, most = 0.0;
    size_t n = 0, above = 0;
    for (size_t i = 0; i < f.samples.size(); ++i) {
        if (f.reflective[i] <= 0.5f) continue;
        sum += f.samples[i];
        most = std::max(most, double(f.samples[i]));
        above += targetError > 0.0f && f.stderror[i] > targetError;
        ++n;
    }
    return {{"mean", n ? sum / double(n) : 0.0}, {"max", most}, {"pixels", n}, {"pixels_above_target", above}};
}

// The mean of independent seeds: reflection and linear averaged, samples and rays summed, the
// standard error of the mean (-1 stays unknown).
reference::Frame meanOfSeeds(const std::vector<reference::Frame>& seeds) {
    reference::Frame f = seeds.front();
    if (seeds.size() == 1) return f;
    const float n = float(seeds.size());
    for (size_t i = 0; i < f.linear.size(); ++i) {
        glm::vec3 lin(0.0f), refl(0.0f);
        float samples = 0.0f, var = 0.0f;
        bool known = true;
        for (const reference::Frame& s : seeds) {
            lin += s.linear[i];
            refl += s.reflection[i];
            samples += s.samples[i];
            known = known && s.stderror[i] >= 0.0f;
            var += s.stderror[i] * s.stderror[i];
        }
        f.linear[i] = lin / n;
        f.reflection[i] = refl / n;
        f.samples[i] = samples;
        f.stderror[i] = known ? std::sqrt(var) / n : -1.0f;
    }
    f.rays = 0;
    f.seconds = 0.0;
    for (const reference::Frame& s : seeds) {
        f.rays += s.rays;
        f.seconds += s.seconds;
    }
    return f;
}

metrics::Image metricsImage(const reference::Frame& f, const std::vector<float>& channel) {
    metrics::Image img{f.width, f.height, {}};
    img.pixels.reserve(channel.size());
    for (float v : channel) img.pixels.push_back(glm::vec3(v));
    return img;
}

// How far two seeds agree (docs: tests/reference/README.md, "converged references"): PSNR of one
// against the other on the reflective pixels where both are converged (standard error at most
// --max-reference-error, metrics::kMaxReferenceError by default), per band (mirror: roughness
// below reference::kRoughBand), and how many reflective pixels were left out as unconverged. The
// mean that is written is closer to the truth than either seed: its own error is about 3 dB below
// this figure.
nlohmann::json seedAgreement(const reference::Frame& a, const reference::Frame& b, float exposure, float maxError) {
    metrics::Image ia{a.width, a.height, a.reflection}, ib{b.width, b.height, b.reflection};
    metrics::Image reflective = metricsImage(a, a.reflective), rough = metricsImage(a, a.roughness);
    std::vector<uint8_t> mask = metrics::reflectiveMask(a.width, a.height, &reflective, nullptr);
    size_t unconverged = 0;
    mask = metrics::convergedMask(mask, metricsImage(a, a.stderror), maxError, unconverged);
    mask = metrics::convergedMask(mask, metricsImage(b, b.stderror), maxError, unconverged);
    auto band = [&](float lo, float hi) {
        metrics::Scores s = metrics::compare(ia, ib, metrics::bandMask(mask, rough, lo, hi), exposure);
        return nlohmann::json{{"pixels", s.pixels}, {"psnr_db", s.psnr ? nlohmann::json(*s.psnr) : nlohmann::json()}};
    };
    return {{"mirror", band(0.0f, reference::kRoughBand)}, {"rough", band(reference::kRoughBand, 1e9f)},
            {"unconverged_pixels", unconverged}, {"max_reference_error", maxError}};
}

int run(const Options& o) {
    const reference::Options& r = o.render;
    if (o.out.empty()) throw argumentError("--out DIR is required");
    if (o.view.scenePath.empty()) throw argumentError("--scene FILE is required");
    if (r.spp < 1 || r.spp > 1u << 20) throw argumentError("--spp must be in 1..1048576");
    if (r.maxSpp != 0 && (r.maxSpp < r.spp || r.maxSpp > 1u << 24))
        throw argumentError("--max-spp must be 0 (no adaptive sampling) or in --spp..16777216");
    if (r.roughMaxSpp != 0 && (r.roughMaxSpp < r.spp || r.roughMaxSpp > 1u << 24))
        throw argumentError("--rough-max-spp must be 0 (--max-spp) or in --spp..16777216");
    if (!(r.targetError >= 0.0f && r.targetError < 1.0f)) throw argumentError("--target-error must be in [0, 1)");
    if (r.minBatches < 2 || r.minBatches > 4096) throw argumentError("--min-batches must be in 2..4096");
    if (o.seeds < 1 || o.seeds > 16) throw argumentError("--seeds must be in 1..16");
    if (!(o.maxReferenceError > 0.0f && o.maxReferenceError <= 1.0f))
        throw argumentError("--max-reference-error must be in (0, 1]");
    if (r.bounces < 1 || r.bounces > 64) throw argumentError("--bounces must be in 1..64");
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
    reference::Options ropt = r;
    ropt.exposure = ro.exposure;
    size_t frameIndex = 0;
    auto frameStart = std::chrono::steady_clock::now();
    ropt.progress = [&](uint32_t done, uint32_t total) { progressBar(frameIndex, views.size(), done, total, frameStart); };
    // One renderer a seed (seed, seed + 1, ...): independent estimates of the same image.
    std::vector<std::unique_ptr<reference::Renderer>> renderers;
    for (uint32_t k = 0; k < o.seeds; ++k) {
        ropt.seed = r.seed + k;
        renderers.push_back(std::make_unique<reference::Renderer>(scene, ropt));
    }
    const reference::Renderer& renderer = *renderers.front();
    double setupSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();

    nlohmann::json frames = nlohmann::json::array();
    for (frameIndex = 0; frameIndex < views.size(); ++frameIndex) {
        frameStart = std::chrono::steady_clock::now();
        std::vector<reference::Frame> perSeed;
        for (const auto& seedRenderer : renderers) perSeed.push_back(seedRenderer->render(views[frameIndex]));
        reference::Frame f = meanOfSeeds(perSeed);
        for (const std::string& a : aovs) app::writeAov(o.out, a, int(frameIndex), toAov(f, a, renderer.exposure()));
        double raysPerSecond = f.rays / std::max(f.seconds, 1e-9);
        nlohmann::json entry = {{"frame", frameIndex}, {"seconds", f.seconds}, {"rays", f.rays},
                                {"rays_per_second", raysPerSecond}, {"samples", sampleStats(f, r.targetError)}};
        if (perSeed.size() >= 2)
            entry["seed_agreement"] = seedAgreement(perSeed[0], perSeed[1], renderer.exposure(), o.maxReferenceError);
        frames.push_back(entry);
        std::printf("reference frame %zu: %.2f s, %.2f Mrays, %.2f Mrays/s\n", frameIndex, f.seconds, f.rays / 1e6,
                    raysPerSecond / 1e6);
    }
    nlohmann::json report = {{"scene", o.view.scenePath},         {"width", w},
                             {"height", h},              {"spp", r.spp},
                             {"bounces", r.bounces},     {"seed", r.seed}, {"seeds", o.seeds},
                             {"target_error", r.targetError}, {"min_batches", r.minBatches},
                             {"max_spp", r.maxSpp}, {"rough_max_spp", r.roughMaxSpp},
                             {"max_reference_error", o.maxReferenceError},
                             {"threads", r.threads},     {"exposure", renderer.exposure()},
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
    cli.add_option("--spp", o.render.spp, "glossy reflection samples per pixel, or per batch with --target-error (default 64)");
    cli.add_option("--target-error", o.render.targetError,
                   "adaptive sampling: batches of --spp until the standard error in display units is at most this (default 0: off)");
    cli.add_option("--max-spp", o.render.maxSpp, "adaptive sampling: at most this many samples a pixel (default 0: --spp)");
    cli.add_option("--rough-max-spp", o.render.roughMaxSpp,
                   "adaptive sampling: the cap for reflection roughness >= 0.3, the rough band (default 0: --max-spp)");
    cli.add_option("--seeds", o.seeds,
                   "render seeds --seed..--seed+N-1 and write their mean; with 2 or more, reference.json reports their agreement (default 1)");
    cli.add_option("--max-reference-error", o.maxReferenceError,
                   "the seed agreement leaves out pixels whose standard error is above this; scorers read it from "
                   "reference.json (default 0.01)");
    cli.add_option("--min-batches", o.render.minBatches, "adaptive sampling: at least this many batches (default 4)");
    cli.add_option("--bounces", o.render.bounces, "reflective surfaces traced this deep (default 2)");
    cli.add_option("--seed", o.render.seed, "random seed (same seed, same image; default 1)");
    cli.add_option("--threads", o.render.threads, "render threads (default: all hardware threads)");
    app::addSettingsOptions(cli, o.settingsFile, o.sets, "render.exposure");
    cli.add_option("--aov", o.aov,
                   "comma list: linear,color,reflection,depth,normal,reflective (default linear,color,reflection,reflective)");
    cli.add_option("--out", o.out, "output directory");
    return app::toolMain("speculum-reference", cli, argc, argv, [&] {
        o.settingsGiven = cli.count("--settings") > 0;
        return run(o);
    });
}
