#include "speculum/chain.hpp"

#include <algorithm>

namespace speculum::chain {

std::vector<app::ModuleInfo> moduleInfos() {
    return {probes::moduleInfo(), reflections::moduleInfo()};
}

bool probesInUse(const Settings& settings) {
    return settings.getBool("reflections.enabled") && settings.getBool("reflections.probes");
}

Chain::Chain(const gpu::Context& ctx, render::Renderer& renderer, const Settings& settings)
    : probes_(ctx, renderer, fromSettings<probes::ProbeSettings>(settings)), reflections_(ctx, renderer) {}

bool Chain::update(const Settings& settings, const probes::Probes::Progress& progress) {
    if (!probesInUse(settings)) return false;
    probes_.update(progress);
    return true;
}

app::LitHook Chain::litHook(const Settings& settings, const render::FrameInputs& frame) {
    reflections::ReflectionSettings s = fromSettings<reflections::ReflectionSettings>(settings);
    // A host's settings may lack the probes' table (a test of the reflections module alone).
    probes::DebugView probeView = settings.find("probes.debug_view") ? probes::DebugView(settings.getInt("probes.debug_view"))
                                                                     : probes::DebugView::None;
    app::LitHook hook;
    hook.modules = moduleInfos();
    hook.moduleSpecular = s.enabled;
    if (!s.enabled) {
        // A frame without the module: the next one must not reproject this one's image.
        reflections_.resetHistory();
        hook.addPasses = [](FrameGraph&, const render::GBuffer&, TextureHandle lit, app::ModuleAovs&) { return lit; };
        return hook;
    }
    // Planar probes are view-dependent: rendered for this frame's camera before its graph runs.
    if (s.probes)
        probes_.renderPlanar(frame, settings.find("probes.planar_interval") ? settings.getInt("probes.planar_interval") : 1);
    hook.addPasses = [this, s, frame, probeView](FrameGraph& graph, const render::GBuffer& gbuffer, TextureHandle lit,
                                                 app::ModuleAovs& aovs) {
        const auto& asked = aovs.requested;
        bool hizView = std::find(asked.begin(), asked.end(), "hiz") != asked.end();
        probes::ProbeSet set = probes_.addPasses(graph, s.probes, s.cmos);
        reflections::ReflectionOutputs out = reflections_.addPasses(graph, {gbuffer, lit, frame, set}, s, hizView);
        aovs.provided["reflection"] = {out.reflection, 3};
        aovs.provided["method"] = {out.method, 4};
        aovs.provided["iterations"] = {out.hit, 1, 3};
        // xy hit pixel, z hit depth (< 0: the miss code of modules/reflections/shaders/trace.comp), w iterations.
        aovs.provided["hit"] = {out.hit, 4};
        // Without CMOs in the chain the hit image stands in: zeros are not written for it.
        if (out.cmoInfo.valid()) aovs.provided["cmo"] = {out.cmoInfo, 4};
        if (hizView) aovs.provided["hiz"] = {out.hizView, 3};
        if (probeView != probes::DebugView::None) return probes_.addDebugView(graph, gbuffer, frame, set, probeView);
        return out.lit;
    };
    return hook;
}

}  // namespace speculum::chain
