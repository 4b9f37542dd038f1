// reflections.* settings: the one table (name, unit, range, default, help, field) behind JSON,
// --set, the editor panel, ReflectionSettings, the README's table and the tests.
#include "speculum/reflections/reflections.hpp"

namespace speculum::reflections {

const SettingFields<ReflectionSettings>& ReflectionSettings::fields() {
    using T = SettingType;
    using R = ReflectionSettings;
    static const SettingFields<R> table({
        bind<&R::enabled>({"reflections.enabled", T::Bool, "", 0, 1, 1, {},
         "Run the reflections module; off leaves the renderer's prefiltered-environment specular."}),
        bind<&R::screenSpace>({"reflections.screen_space", T::Bool, "", 0, 1, 1, {},
         "Trace screen space first in the fallback chain; off: probes and the sky only (the bench's "
         "`probes` method)."}),
        bind<&R::trace>({"reflections.trace", T::Enum, "", 0, 1, 0, {"hiz", "linear"},
         "Screen-space tracer: hierarchical min/max Hi-Z traversal, or the linear march with binary "
         "refinement kept as the baseline."}),
        bind<&R::maxIterations>({"reflections.max_iterations", T::Int, "", 1, 1024, 96, {},
         "Hi-Z: most traversal iterations per ray (a ray out of iterations is a miss)."}),
        bind<&R::linearPreSteps>({"reflections.linear_pre_steps", T::Int, "", 0, 16, 2, {},
         "Hi-Z: steps at level 0 before the hierarchy, to leave the reflecting surface cheaply."}),
        bind<&R::hizStartLevel>({"reflections.hiz_start_level", T::Int, "", 0, 12, 1, {},
         "Hi-Z: level the hierarchical traversal starts at after the linear steps."}),
        bind<&R::hizStopLevel>({"reflections.hiz_stop_level", T::Int, "", 0, 6, 0, {},
         "Hi-Z: level at which an overlap counts as a hit (0 = per pixel; higher is coarser and faster)."}),
        bind<&R::linearStride>({"reflections.linear_stride", T::Float, "px", 1, 64, 2, {},
         "Linear march: step length along the ray's major screen axis."}),
        bind<&R::linearMaxSteps>({"reflections.linear_max_steps", T::Int, "", 1, 4096, 512, {},
         "Linear march: most steps per ray before the binary refinement."}),
        bind<&R::refineSteps>({"reflections.refine_steps", T::Int, "", 0, 16, 5, {},
         "Linear march: binary-search steps between the last miss and the first hit."}),
        bind<&R::thickness>({"reflections.thickness", T::Float, "x depth", 0.001, 4, 0.08, {},
         "Assumed thickness of every surface as a fraction of its distance to the eye: rays "
         "further behind a surface than this pass behind it."}),
        bind<&R::coneSamples>({"reflections.cone_samples", T::Int, "", 1, 32, 8, {},
         "Cone tracing: most incircle samples per ray (stops earlier at full visibility)."}),
        bind<&R::coverage>({"reflections.coverage", T::Enum, "", 0, 1, 0, {"hit", "visibility"},
         "Screen-space share of a pixel: `hit` (a hit covers fully, times the fades) or "
         "`visibility` (the cone's accumulated pre-integrated visibility, as in the book)."}),
        bind<&R::maxRoughness>({"reflections.max_roughness", T::Float, "", 0, 1, 0.6, {},
         "Screen space is used up to this perceptual roughness (materials can lower it); the "
         "environment takes over above it, faded over the last 0.1."}),
        bind<&R::edgeFade>({"reflections.edge_fade", T::Float, "x screen", 0, 0.5, 0.05, {},
         "Hits closer to a screen edge than this share of the screen fade to the fallback."}),
        bind<&R::cameraFadeStart>({"reflections.camera_fade_start", T::Float, "cos", -1, 1, -0.2, {},
         "Rays toward the camera: fading starts where dot(ray, view direction) drops below this."}),
        bind<&R::cameraFadeEnd>({"reflections.camera_fade_end", T::Float, "cos", -1, 1, -0.6, {},
         "Rays toward the camera: fully faded below this dot(ray, view direction)."}),
        bind<&R::distanceFadeStart>({"reflections.distance_fade_start", T::Float, "m", 0, 10000, 40, {},
         "Hits further than this from the reflecting point start fading."}),
        bind<&R::distanceFadeEnd>({"reflections.distance_fade_end", T::Float, "m", 0, 10000, 60, {},
         "Hits further than this from the reflecting point are fully faded."}),
        bind<&R::multiBounce>({"reflections.multi_bounce", T::Bool, "", 0, 1, 1, {},
         "Build the colour pyramid from the previous frame's final image reprojected, so "
         "reflections of reflections accumulate over frames."}),
        bind<&R::hitReflectMaxRoughness>({"reflections.hit_reflect_max_roughness", T::Float, "", 0, 1, 0.3, {},
         "A screen-space hit on a reflective surface smoother than this is shaded for the reflected "
         "ray: the surface's lit colour plus its own reflection along the ray reflected again, "
         "from the probes and the sky (the colour pyramid holds its reflection toward the camera, "
         "another direction), and a CMO hit on a reflective metal smoother than this reflects again "
         "through the CMOs (up to cmo_bounces: what the CMO captured of it faced its centre). 0: the "
         "colour pyramid's and the CMO's captured value everywhere."}),
        bind<&R::probes>({"reflections.probes", T::Bool, "", 0, 1, 1, {},
         "Local cubemap probes (modules/probes) between screen space and the sky in the fallback "
         "chain, and planar probes on their planes; off: what screen space leaves goes to the sky."}),
        bind<&R::cmos>({"reflections.cmos", T::Bool, "", 0, 1, 1, {},
         "Cubemap-tracing objects (CMOs, SPECULUM_reflection_probe kind cmo) between screen space "
         "and the local probes in the fallback chain: what screen space leaves is traced through "
         "them in order; off: it goes to the local probes."}),
        bind<&R::cmoTrace>({"reflections.cmo_trace", T::Enum, "", 0, 1, 0, {"hierarchical", "linear"},
         "CMO tracer: the min/max distance hierarchy per cube face (skips what the ray cannot "
         "meet), or constant world steps with bisection kept as the baseline."}),
        bind<&R::cmoMaxIterations>({"reflections.cmo_max_iterations", T::Int, "", 1, 4096, 256, {},
         "CMO tracing: most cells (hierarchical) or steps (linear) per pixel over every CMO and "
         "bounce; a ray out of iterations is unresolved and goes on down the chain."}),
        bind<&R::cmoLinearStep>({"reflections.cmo_linear_step", T::Float, "m", 0.001, 10, 0.05, {},
         "CMO linear tracer: the constant step along the ray."}),
        bind<&R::cmoThickness>({"reflections.cmo_thickness", T::Float, "m", 0, 10, 0.05, {},
         "CMO tracing: how far behind a captured surface a crossing found at a texel's edge may "
         "lie and still be that surface (plus four texel footprints); deeper, the ray passed "
         "behind it and the next CMO is asked."}),
        bind<&R::cmoMaxDistance>({"reflections.cmo_max_distance", T::Float, "m", 0.1, 10000, 60, {},
         "CMO tracing: the length of a traced ray; beyond it the ray is a miss (local probes, sky)."}),
        bind<&R::cmoBounces>({"reflections.cmo_bounces", T::Int, "", 0, 8, 1, {},
         "CMO self-reflections: a hit on a mirror-masked material (SPECULUM_reflections "
         "mirrorForSelfReflections), or on a reflective metal smoother than hit_reflect_max_roughness, "
         "reflects again, up to this many times. 1: a second self-reflection scored the bench's "
         "mirror band 0.03 dB higher (gallery.floor_grazing +0.33, the rest within 0.06) for 3-11% of "
         "the CMO trace; raise it for facing mirrors (modules/reflections/MEASUREMENTS.md, 2026-12-06)."}),
        bind<&R::cmoPassBehind>({"reflections.cmo_unresolved", T::Enum, "", 0, 1, 0, {"probes", "pass_behind"},
         "A ray every CMO leaves unresolved (it passed behind a surface the CMOs cannot see past): "
         "down the chain to the local probes, or traced once more through the first CMO as if it "
         "passed behind what hid it (right behind thin occluders, wrong where it meets one's "
         "unseen back)."}),
        // 0.25, not 0.5 (issue 23, reflections/MEASUREMENTS.md 2026-12-07): the gallery's 0.3 floor
        // band was a fifth of reflections.cmo_trace there, two thirds of its rays ended unresolved,
        // and the local probes scored it 0.07 dB higher; no view of the bench's scenes (the closed
        // room's placed CMOs included) lost more than 0.03 dB in its mirror band without it.
        bind<&R::cmoMaxRoughness>({"reflections.cmo_max_roughness", T::Float, "", 0, 1, 0.25, {},
         "CMOs trace reflections up to this perceptual roughness (glossy rays read the colour "
         "mips by the cone's footprint at the hit); rougher goes to the local probes."}),
        bind<&R::resolution>({"reflections.resolution", T::Enum, "", 0, 1, 0, {"full", "half"},
         "Trace and resolve at full size, or at half size in each axis followed by a joint bilateral "
         "upsampling guided by full-resolution depth, normal and material (about 4x fewer rays)."}),
        bind<&R::fullResLookups>({"reflections.full_res_lookups", T::Bool, "", 0, 1, 0, {},
         "Half resolution: pixels whose trace pixel found no screen-space or CMO hit take the "
         "planar probe, local probes and sky at their own full-resolution position instead of "
         "the upsampled value: sharper curved mirrors (+0.2 to +1.8 dB in the mirror band) for "
         "one more full-size pass (38 ms at 960x540 on lavapipe, twice the upsampling)."}),
        // Off by default for lavapipe's sake: it runs every branch for every pixel, so the passes
        // cost all of their code wherever they are dispatched (35-45 ms on gallery.main and
        // cornell_mirrors.main at 960x540, about the upsampling twice; `low` would cost 0.68-1.1x
        // the default with it); a GPU skips the branches a pixel does not take (MEASUREMENTS.md,
        // issue 23, "hit reuse").
        bind<&R::hitReuse>({"reflections.hit_reuse", T::Bool, "", 0, 1, 0, {},
         "Half resolution: a mirror pixel its 2x2 did not trace takes its own hit, found from its "
         "neighbours' (screen space, the CMOs, the sky) where its own ray meets the surfaces they "
         "hit, instead of the upsampled value: sharper curved mirrors (+0.9 to +1.1 dB in the mirror "
         "band) for one or two more full-size passes (18-45 ms at 960x540 on lavapipe)."}),
        bind<&R::tiles>({"reflections.tiles", T::Bool, "", 0, 1, 1, {},
         "Classify 8x8 tiles by what their pixels need (a screen-space ray, the CMOs, a probe and sky "
         "lookup, nothing) and run the trace, the CMO trace and the resolve only where needed, by "
         "indirect dispatch; off: each over the whole screen (the same image, the A/B baseline)."}),
        bind<&R::rayBudget>({"reflections.ray_budget", T::Enum, "", 0, 1, 0, {"full", "quarter"},
         "Screen-space rays per frame: one per pixel, or one per 2x2 block (the half-size grid, "
         "whatever reflections.resolution says) whose pixel rotates over four frames; the other "
         "three pixels keep their last traced value where the history is valid (a still camera "
         "reaches the full-rate image in four frames) and take the bilateral upsampling elsewhere."}),
        bind<&R::glossy>({"reflections.glossy", T::Enum, "", 0, 1, 0, {"cone", "stochastic"},
         "Glossy reflections by cone tracing the mirror ray's hit in the colour pyramid, or by one "
         "GGX visible-normal sample per pixel with neighbour ray reuse (pair it with temporal)."}),
        bind<&R::temporal>({"reflections.temporal", T::Bool, "", 0, 1, 0, {},
         "Accumulate the reflection over frames: history reprojected by the surface (rough) and by "
         "the reflected hit (sharp), rejected on disocclusion, clipped to the neighbourhood."}),
        bind<&R::temporalAlpha>({"reflections.temporal_alpha", T::Float, "", 0.02, 1, 0.1, {},
         "Temporal: weight of the current frame (1 = no accumulation; 0.1 averages about 10 frames)."}),
        bind<&R::temporalClip>({"reflections.temporal_clip", T::Float, "sigma", 0.25, 8, 1.25, {},
         "Temporal: the history is clipped to the current 3x3 mean +- this many standard "
         "deviations (lower: less ghosting, more flicker)."}),
        bind<&R::debugView>({"reflections.debug_view", T::Enum, "", 0, 8, 0,
         {"none", "iterations", "hit_mask", "coverage", "method", "hiz", "reflection", "cmo", "tiles"},
         "Replace the image with a debug view: iterations heatmap, hit mask, screen-space coverage, "
         "method weights (CMOs yellow), a Hi-Z level, the reflection alone, CMO tracing (hue: "
         "which CMO hit, brightness: iterations; red: unresolved), or the 8x8 tile classes (green "
         "a screen-space ray, blue a lookup only; yellow and magenta: the same with CMOs)."}),
        bind<&R::debugHizMip>({"reflections.debug_hiz_mip", T::Int, "", 0, 15, 3, {},
         "Hi-Z level shown by debug_view=hiz and the hiz AOV."}),
    });
    return table;
}

std::vector<SettingDesc> settingsTable() { return ReflectionSettings::fields().descs(); }

app::ModuleInfo moduleInfo() {
    return {"reflections",
            settingsTable(),
            {{"reflection", "pre-Fresnel reflection radiance (rgb), 0 where nothing reflects"},
             {"method", "fallback chain weights: r screen space, g local probes, b sky, a CMOs (sum 1)"},
             {"cmo", "CMO tracing per pixel (at the trace's resolution): x iterations, y the CMO that hit "
                     "(1-based; 0 none), z 1 hit, 2 unresolved, w self-reflection bounces"},
             {"iterations", "screen-space trace iterations per pixel (at the trace's resolution: half size with "
                            "reflections.resolution=half)"},
             {"hiz", "closest and farthest depth of the pixel's cell at reflections.debug_hiz_mip"},
             {"hit", "trace output: hit pixel x, y, hit depth or a negative miss code, iterations (at the "
                     "trace's resolution)"}},
            "reflections.debug_view",
            "reflections.enabled"};
}

ReflectionSettings::ReflectionSettings() { fields().writeDefaults(*this); }

}  // namespace speculum::reflections
