// Builds, compiles and executes one frame graph per frame for a renderer, and reads back
// images. Shared by speculum-capture, speculum-game, the tests and the bench.
#pragma once

#include "speculum/app/module.hpp"
#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/render/renderer.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace speculum::app {

// AOVs the engine writes itself; modules register theirs (ModuleInfo::aovs).
const std::vector<std::string>& availableAovs();

struct AovImage {
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t channels = 4;      // channels that carry data (1: depth/roughness, 2: motion, ...)
    std::vector<float> rgba;    // width * height * 4
};

struct PassTime {
    std::string name;
    double ms = 0.0;
};

struct FrameResult {
    std::map<std::string, AovImage> aovs;
    std::vector<PassTime> passes;  // GPU timestamps, execution order
    double frameMs = 0.0;          // sum of the engine's passes (readback excluded)
    MemoryStats memory;            // transient peak with and without aliasing
};

// A readback source: which graph texture an AOV comes from and how its channels map.
struct AovSource {
    TextureHandle texture;
    uint32_t channels = 4;   // channels that carry data
    int sourceChannel = -1;  // >= 0: the AOV is this single channel of the texture
};

// What a LitHook sees of the frame's AOV request, and where it registers the AOVs it provides
// (so that a module adds debug passes only when someone reads them).
struct ModuleAovs {
    std::vector<std::string> requested;
    std::map<std::string, AovSource> provided;
};

// The host's module chain for one frame: passes between lighting and tonemapping. `addPasses`
// returns the (possibly new) lit handle.
struct LitHook {
    std::function<TextureHandle(FrameGraph&, const render::GBuffer&, TextureHandle lit, ModuleAovs&)> addPasses;
    // The chain composites the specular ambient of reflective pixels itself this frame, so
    // render.lighting leaves it out (render::LightingOptions::moduleSpecular).
    bool moduleSpecular = false;
    // What the chain's modules registered: render() accepts their AOVs and names them in errors.
    std::vector<ModuleInfo> modules;
    explicit operator bool() const { return bool(addPasses); }
};
// Adds passes after tonemapping (presentation).
using PresentHook = std::function<void(FrameGraph&, TextureHandle color)>;

class FrameRunner {
public:
    FrameRunner(const gpu::Context& ctx, render::Renderer& renderer, uint32_t width, uint32_t height);
    ~FrameRunner();
    FrameRunner(const FrameRunner&) = delete;
    FrameRunner& operator=(const FrameRunner&) = delete;

    // Records one frame, submits it and waits. `aovs` names the images to read back.
    FrameResult render(const render::FrameInputs& frame, const std::vector<std::string>& aovs,
                       const LitHook& litHook = {}, const PresentHook& presentHook = {},
                       VkSemaphore wait = VK_NULL_HANDLE, VkSemaphore signal = VK_NULL_HANDLE);

    void resize(uint32_t width, uint32_t height);
    // The last compiled graph as DOT / JSON (passes, resources, barriers, memory, timings).
    std::string graphDot() const;
    nlohmann::json graphJson() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace speculum::app
