// probes.* settings: the one table behind JSON, --set, the editor panel and the tests.
#include "speculum/probes/probes.hpp"

namespace speculum::probes {

std::vector<SettingDesc> settingsTable() {
    using T = SettingType;
    return {
        {"probes.bounces", T::Int, "", 1, 8, 2, {},
         "Bakes of every probe at start, each seeing the one before: reflective surfaces in a "
         "probe show the probes' previous bake (bounce 1 sees only the sky)."},
        {"probes.prefilter_samples", T::Int, "", 1, 1024, 64, {},
         "GGX samples per texel when prefiltering a probe's rough mips (as the sky's)."},
        {"probes.prefilter_slice", T::Int, "k texel-samples", 1, 100000, 512, {},
         "Prefilter work a time-sliced probe does per update after its six faces (1024 GGX "
         "samples of one texel = 1): 512 is about one 256^2 face's capture on lavapipe, so the "
         "prefilter is spread over the next ~17 updates instead of one 0.2-0.9 s hitch."},
        {"probes.debug_view", T::Enum, "", 0, 2, 0, {"none", "influence", "winner"},
         "Replace the image with the probes' blend (each probe's colour times its share, the sky "
         "dark blue) or the probe with the largest share."},
    };
}

app::ModuleInfo moduleInfo() {
    return {"probes", settingsTable(), {}, "probes.debug_view", ""};
}

ProbeSettings::ProbeSettings() : ProbeSettings(from(Settings(settingsTable()))) {}

ProbeSettings ProbeSettings::from(const Settings& s) {
    ProbeSettings p{Blank{}};
    p.bounces = s.getInt("probes.bounces");
    p.prefilterSamples = s.getInt("probes.prefilter_samples");
    p.prefilterSlice = s.getInt("probes.prefilter_slice");
    p.debugView = DebugView(s.getInt("probes.debug_view"));
    return p;
}

}  // namespace speculum::probes
