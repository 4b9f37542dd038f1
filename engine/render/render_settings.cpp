// The engine's settings (render.*): the one table behind JSON, --set, the editor panel,
// RendererOptions and EnvironmentOptions (their defaults) and the root README's table. It lives
// in the render layer because the options it fills do; the platform layer hands it to hosts as
// app::engineSettingsTable().
#include "speculum/render/renderer.hpp"

namespace speculum::render {

const SettingFields<EnvironmentOptions>& EnvironmentOptions::fields() {
    using E = EnvironmentOptions;
    static const SettingFields<E> table({
        bind<&E::cubeSize>({"render.environment_size", SettingType::Int, "px", 16, 2048, 256, {},
         "Face size of the prefiltered environment cubemap's mip 0."}),
        bind<&E::prefilterSamples>({"render.environment_samples", SettingType::Int, "", 1, 1024, 64, {},
         "GGX samples per texel when prefiltering the environment's rough mips."}),
    });
    return table;
}

const SettingFields<RendererOptions>& RendererOptions::fields() {
    using R = RendererOptions;
    static const SettingFields<R> table = [] {
        std::vector<SettingField<R>> rows = {
            bind<&R::exposure>({"render.exposure", SettingType::Float, "x", 0.001, 1000.0, 1.0, {},
             "Linear exposure multiplier before tonemapping; multiplies the scene's extras.exposure."}),
            bind<&R::shadowMapSize>({"render.shadow_map_size", SettingType::Int, "px", 64, 8192, 2048, {},
             "Edge of the directional light's shadow map."}),
        };
        for (SettingField<R>& row : EnvironmentOptions::fields().within(&R::environment)) rows.push_back(std::move(row));
        return SettingFields<R>(std::move(rows));
    }();
    return table;
}

}  // namespace speculum::render
