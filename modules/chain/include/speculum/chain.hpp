// The reflection chain as hosts run it: the probes module, then the reflections module, which
// takes the probes' handles (modules/chain/README.md). Every host (speculum-capture, the editor's
// viewport, the game, the tests) composes the modules through one Chain, so they all run them
// the same way and none repeats the composition; the engine knows neither module.
#pragma once

#include "speculum/app/frame_runner.hpp"
#include "speculum/app/module.hpp"
#include "speculum/probes/probes.hpp"
#include "speculum/reflections/reflections.hpp"

#include <vector>

namespace speculum::chain {

// The hosted modules in chain order (probes, reflections): their settings tables, AOVs and
// debug views, which hosts register (app::settingsOf, --aov, the editor's panels).
std::vector<app::ModuleInfo> moduleInfos();

// Whether this frame's chain reads the probes (reflections and reflections.probes on): hosts
// update the probes only then, so a run without them bakes nothing.
bool probesInUse(const Settings& settings);

class Chain {
public:
    // The probes take their bake settings (probes.*) from `settings` now; the reflections
    // module reads its settings every frame (the editor changes them live).
    Chain(const gpu::Context& ctx, render::Renderer& renderer, const Settings& settings);

    // The probes' captures and prefilters for this frame, when the chain reads them (their
    // graphs run before the frame's). Returns whether they were updated.
    bool update(const Settings& settings, const probes::Probes::Progress& progress = {});
    // Plugs the chain into app::FrameRunner between render.lighting and render.tonemap and
    // provides the modules' AOVs. With reflections.enabled off the renderer keeps its own
    // specular ambient and the module forgets its history; reflections.probes=false hands the
    // module a probe set with no probe in it.
    app::LitHook litHook(const Settings& settings, const render::FrameInputs& frame);
    // The next frame must not reproject this one (a resize, a camera cut).
    void resetHistory() { reflections_.resetHistory(); }

    probes::Probes& probes() { return probes_; }
    const probes::Probes& probes() const { return probes_; }
    reflections::Reflections& reflections() { return reflections_; }

private:
    probes::Probes probes_;
    reflections::Reflections reflections_;  // after the probes: destroyed first
};

}  // namespace speculum::chain
