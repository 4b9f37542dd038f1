#include "speculum/reflections/hook.hpp"

#include <algorithm>

namespace speculum::reflections {

bool probesInUse(const Settings& settings) {
    return settings.getBool("reflections.enabled") && settings.getBool("reflections.probes");
}

app::LitHook litHook(Reflections& module, probes::Probes* probes, const Settings& settings,
                     const render::FrameInputs& frame) {
    ReflectionSettings s = fromSettings<ReflectionSettings>(settings);
    // The probes' debug view, when the host's settings carry the probes' table.
    probes::DebugView probeView = probes && settings.find("probes.debug_view")
                                      ? probes::DebugView(settings.getInt("probes.debug_view"))
                                      : probes::DebugView::None;
    app::LitHook hook;
    hook.modules = {moduleInfo()};
    if (probes) hook.modules.insert(hook.modules.begin(), probes::moduleInfo());
    hook.moduleSpecular = s.enabled;
    if (!s.enabled) {
        // A frame without the module: the next one must not reproject this one's image.
        module.resetHistory();
        hook.addPasses = [](FrameGraph&, const render::GBuffer&, TextureHandle lit, app::ModuleAovs&) { return lit; };
        return hook;
    }
    hook.addPasses = [&module, probes, s, frame, probeView](FrameGraph& graph, const render::GBuffer& gbuffer, TextureHandle lit,
                                                 app::ModuleAovs& aovs) {
        const auto& asked = aovs.requested;
        bool hizView = std::find(asked.begin(), asked.end(), "hiz") != asked.end();
        probes::ProbeSet set = probes ? probes->addPasses(graph, s.probes, s.cmos) : probes::ProbeSet{};
        ReflectionOutputs out = module.addPasses(graph, {gbuffer, lit, frame, set}, s, hizView);
        aovs.provided["reflection"] = {out.reflection, 3};
        aovs.provided["method"] = {out.method, 4};
        aovs.provided["iterations"] = {out.hit, 1, 3};
        // xy hit pixel, z hit depth (< 0: the miss code of shaders/reflections/trace.comp), w iterations.
        aovs.provided["hit"] = {out.hit, 4};
        // Without CMOs in the chain the hit image stands in: zeros are not written for it.
        if (out.cmoInfo.valid()) aovs.provided["cmo"] = {out.cmoInfo, 4};
        if (hizView) aovs.provided["hiz"] = {out.hizView, 3};
        if (probeView != probes::DebugView::None) return probes->addDebugView(graph, gbuffer, frame, set, probeView);
        return out.lit;
    };
    return hook;
}

}  // namespace speculum::reflections
