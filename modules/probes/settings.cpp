// probes.* settings: the one table behind JSON, --set, the editor panel, ProbeSettings and the
// tests.
#include "speculum/probes/probes.hpp"

namespace speculum::probes {

const SettingFields<ProbeSettings>& ProbeSettings::fields() {
    using T = SettingType;
    using P = ProbeSettings;
    static const SettingFields<P> table({
        bind<&P::bounces>({"probes.bounces", T::Int, "", 1, 8, 2, {},
         "Bakes of every probe at start, each seeing the one before: reflective surfaces in a "
         "probe show the probes' previous bake (bounce 1 sees only the sky)."}),
        bind<&P::prefilterSamples>({"probes.prefilter_samples", T::Int, "", 1, 1024, 64, {},
         "GGX samples per texel when prefiltering a probe's rough mips (as the sky's)."}),
        bind<&P::prefilterSlice>({"probes.prefilter_slice", T::Int, "k texel-samples", 1, 100000, 512, {},
         "Prefilter work a time-sliced probe does per update after its six faces (1024 GGX "
         "samples of one texel = 1): 512 is about one 256^2 face's capture on lavapipe, so the "
         "prefilter is spread over the next ~17 updates instead of one 0.2-0.9 s hitch."}),
        bind<&P::planarInterval>({"probes.planar_interval", T::Int, "frames", 1, 8, 1, {},
         "Render the planar probes every this many frames; the frames between reuse the last "
         "images (the reflection lags the camera by up to this less one frame). low.json has 2: "
         "the editor's interactive frames at 330x256 spend 12 of about 75 ms on lavapipe "
         "rendering gallery's floor probe."}),
        bind<&P::planarScale>({"probes.planar_scale", T::Float, "x view height", 0.125, 1, 0.5, {},
         "A planar probe without a resolution of its own renders at this fraction of the view's "
         "height. Half (the default) costs a quarter of the view's pixels; the view's full height "
         "(high.json) makes a sharp mirror floor's reflected edges a pixel wide instead of two: "
         "gallery.main's mirror band 22.70 -> 23.93 dB, for four times the planar render "
         "(modules/probes/MEASUREMENTS.md)."}),
        bind<&P::planarCrop>({"probes.planar_crop", T::Bool, "", 0, 1, 1, {},
         "Render a planar probe's mirrored view only where its rectangle lies on screen (and 12 "
         "texels around it), texel for texel what the whole view holds there; a probe off screen "
         "renders nothing. false: the whole view, for comparison (modules/probes/MEASUREMENTS.md)."}),
        bind<&P::planarGround>({"probes.planar_ground", T::Int, "px", 0, 1024, 128, {},
         "Each planar probe's ground: its rectangle seen straight down, this many pixels a side "
         "(0: none), rendered at load and on a whole-scene re-bake. A reflected ray that meets "
         "the plane from above, in a probe capture, a planar image or the chain's probe step, "
         "reads the floor there instead of the cube, which cannot see under objects standing on "
         "it (closed_room's mirror band +1.8 to +5.5 dB; 128 and 256 px score alike: "
         "modules/probes/MEASUREMENTS.md)."}),
        bind<&P::autoProbe>({"probes.auto_probe", T::Bool, "", 0, 1, 1, {},
         "A scene without a local cubemap probe of its own (a plain export; CMOs and planar "
         "probes do not count: they sit above the local probes in the chain) gets one box probe "
         "fitted to its bounds, baked once at load, so that its metals reflect its own floor and "
         "walls rather than the sky's ground (plain_metals' mirror band 19.1 -> 22.8 dB, "
         "modules/probes/MEASUREMENTS.md). Never saved into the scene; a placed local probe "
         "replaces it."}),
        bind<&P::distanceSteps>({"probes.distance_steps", T::Int, "steps", 0, 32, 4, {},
         "A lobe narrower than roughness 0.3 finds its hit on what a local probe captured (the "
         "distance from the capture point, stored with each face) by this many steps along the "
         "ray to the proxy and two secant steps, instead of on the proxy's box or sphere: objects "
         "inside the probe's volume land where they are seen from the pixel, not from the "
         "capture point (cornell_mirrors' rough band +1.7 to +2.4 dB through its re-baked chrome, "
         "plain_metals' mirror band +0.34); a ray of the chain that lands on a captured smooth "
         "metal reflects again there (failure_cases' mirror band +1.07). 0: the proxy alone. "
         "An object thinner than a step is missed; 8 and 16 steps found no more "
         "(modules/probes/MEASUREMENTS.md)."}),
        bind<&P::debugView>({"probes.debug_view", T::Enum, "", 0, 2, 0, {"none", "influence", "winner"},
         "Replace the image with the probes' blend (each probe's colour times its share, the sky "
         "dark blue) or the probe with the largest share."}),
    });
    return table;
}

std::vector<SettingDesc> settingsTable() { return ProbeSettings::fields().descs(); }

app::ModuleInfo moduleInfo() {
    return {"probes", settingsTable(), {}, "probes.debug_view", ""};
}

ProbeSettings::ProbeSettings() { fields().writeDefaults(*this); }

}  // namespace speculum::probes
