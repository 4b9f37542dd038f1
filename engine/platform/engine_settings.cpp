#include "speculum/app/engine_settings.hpp"

namespace speculum::app {

std::vector<SettingDesc> engineSettingsTable() {
    return {
        {"render.exposure", SettingType::Float, "x", 0.001, 1000.0, 1.0, {},
         "Linear exposure multiplier before tonemapping; multiplies the scene's extras.exposure."},
        {"render.shadow_map_size", SettingType::Int, "px", 64, 8192, 2048, {},
         "Edge of the directional light's shadow map."},
        {"render.environment_size", SettingType::Int, "px", 16, 2048, 256, {},
         "Face size of the prefiltered environment cubemap's mip 0."},
        {"render.environment_samples", SettingType::Int, "", 1, 1024, 64, {},
         "GGX samples per texel when prefiltering the environment's rough mips."},
    };
}

void applyRenderSettings(const Settings& s, render::RendererOptions& options) {
    options.exposure = s.getFloat("render.exposure");
    options.shadowMapSize = static_cast<uint32_t>(s.getInt("render.shadow_map_size"));
    options.environment.cubeSize = static_cast<uint32_t>(s.getInt("render.environment_size"));
    options.environment.prefilterSamples = static_cast<uint32_t>(s.getInt("render.environment_samples"));
}

}  // namespace speculum::app
