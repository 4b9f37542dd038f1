#include "speculum/reflections/hook.hpp"

#include <algorithm>

namespace speculum::reflections {

app::LitHook litHook(Reflections& module, probes::Probes* probes, const Settings& settings,
                     const render::FrameInputs& frame) {
    return [&module, probes, &settings, frame](FrameGraph& graph, const render::GBuffer& gbuffer, TextureHandle lit,
                                        app::ModuleAovs& aovs) {
        ReflectionSettings s = ReflectionSettings::from(settings);
        module.setActive(s.enabled);
        if (!s.enabled) return lit;
        const auto& asked = aovs.requested;
        bool hizView = std::find(asked.begin(), asked.end(), "hiz") != asked.end();
        probes::ProbeSet set = probes ? probes->addPasses(graph, s.probes) : probes::ProbeSet{};
        ReflectionOutputs out = module.addPasses(graph, {gbuffer, lit, frame, set}, s, hizView);
        aovs.provided["reflection"] = {out.reflection, 3};
        aovs.provided["method"] = {out.method, 3};
        aovs.provided["iterations"] = {out.hit, 1, 3};
        // xy hit pixel, z hit depth (< 0: the miss code of shaders/reflections/trace.comp), w iterations.
        aovs.provided["hit"] = {out.hit, 4};
        if (hizView) aovs.provided["hiz"] = {out.hizView, 3};
        return out.lit;
    };
}

}  // namespace speculum::reflections
