// Plugs the module into app::FrameRunner between render.lighting and render.tonemap, and
// provides its AOVs (reflection, method, iterations, hiz). Used by speculum-capture, the game,
// the editor, the tests and the bench, so that they all run the module the same way.
#pragma once

#include "speculum/app/frame_runner.hpp"
#include "speculum/reflections/reflections.hpp"

namespace speculum::reflections {

// Settings are read each frame (the editor changes them live). With reflections.enabled off
// the renderer keeps its own specular ambient and the module forgets its history. `probes`
// (may be null) is composed before the module: its ProbeSet is the module's probe input
// (reflections.probes=false hands it over with no probe in it).
// Whether this frame's chain reads the probes (reflections and reflections.probes on): hosts
// update the probes only then, so a run without them bakes nothing.
bool probesInUse(const Settings& settings);

app::LitHook litHook(Reflections& module, probes::Probes* probes, const Settings& settings,
                     const render::FrameInputs& frame);

}  // namespace speculum::reflections
