// Every setting is described once: the settings structs take their defaults from the table. This
// fails if a struct default and the table differ (a default written twice drifts: the struct once
// said max_iterations 64 and hiz_start_level 2 while the table said 96 and 1).
#include "speculum/probes/probes.hpp"
#include "speculum/reflections/reflections.hpp"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

using namespace speculum;

TEST(ModuleSettings, ReflectionDefaultsComeFromTheTable) {
    Settings table(reflections::settingsTable());
    reflections::ReflectionSettings s;
    EXPECT_EQ(s.enabled, table.getBool("reflections.enabled"));
    EXPECT_EQ(s.screenSpace, table.getBool("reflections.screen_space"));
    EXPECT_EQ(int(s.trace), table.getInt("reflections.trace"));
    EXPECT_EQ(s.maxIterations, table.getInt("reflections.max_iterations"));
    EXPECT_EQ(s.linearPreSteps, table.getInt("reflections.linear_pre_steps"));
    EXPECT_EQ(s.hizStartLevel, table.getInt("reflections.hiz_start_level"));
    EXPECT_EQ(s.hizStopLevel, table.getInt("reflections.hiz_stop_level"));
    EXPECT_FLOAT_EQ(s.linearStride, table.getFloat("reflections.linear_stride"));
    EXPECT_EQ(s.linearMaxSteps, table.getInt("reflections.linear_max_steps"));
    EXPECT_EQ(s.refineSteps, table.getInt("reflections.refine_steps"));
    EXPECT_FLOAT_EQ(s.thickness, table.getFloat("reflections.thickness"));
    EXPECT_EQ(s.coneSamples, table.getInt("reflections.cone_samples"));
    EXPECT_EQ(int(s.coverage), table.getInt("reflections.coverage"));
    EXPECT_FLOAT_EQ(s.maxRoughness, table.getFloat("reflections.max_roughness"));
    EXPECT_FLOAT_EQ(s.edgeFade, table.getFloat("reflections.edge_fade"));
    EXPECT_FLOAT_EQ(s.cameraFadeStart, table.getFloat("reflections.camera_fade_start"));
    EXPECT_FLOAT_EQ(s.cameraFadeEnd, table.getFloat("reflections.camera_fade_end"));
    EXPECT_FLOAT_EQ(s.distanceFadeStart, table.getFloat("reflections.distance_fade_start"));
    EXPECT_FLOAT_EQ(s.distanceFadeEnd, table.getFloat("reflections.distance_fade_end"));
    EXPECT_EQ(s.multiBounce, table.getBool("reflections.multi_bounce"));
    EXPECT_EQ(s.probes, table.getBool("reflections.probes"));
    EXPECT_EQ(s.cmos, table.getBool("reflections.cmos"));
    EXPECT_EQ(int(s.cmoTrace), table.getInt("reflections.cmo_trace"));
    EXPECT_EQ(s.cmoMaxIterations, table.getInt("reflections.cmo_max_iterations"));
    EXPECT_FLOAT_EQ(s.cmoLinearStep, table.getFloat("reflections.cmo_linear_step"));
    EXPECT_FLOAT_EQ(s.cmoThickness, table.getFloat("reflections.cmo_thickness"));
    EXPECT_FLOAT_EQ(s.cmoMaxDistance, table.getFloat("reflections.cmo_max_distance"));
    EXPECT_EQ(s.cmoBounces, table.getInt("reflections.cmo_bounces"));
    EXPECT_FLOAT_EQ(s.cmoMaxRoughness, table.getFloat("reflections.cmo_max_roughness"));
    EXPECT_EQ(s.cmoPassBehind, table.getInt("reflections.cmo_unresolved") == 1);
    EXPECT_EQ(int(s.resolution), table.getInt("reflections.resolution"));
    EXPECT_EQ(int(s.glossy), table.getInt("reflections.glossy"));
    EXPECT_EQ(s.temporal, table.getBool("reflections.temporal"));
    EXPECT_FLOAT_EQ(s.temporalAlpha, table.getFloat("reflections.temporal_alpha"));
    EXPECT_FLOAT_EQ(s.temporalClip, table.getFloat("reflections.temporal_clip"));
    EXPECT_EQ(int(s.debugView), table.getInt("reflections.debug_view"));
    EXPECT_EQ(s.debugHizMip, table.getInt("reflections.debug_hiz_mip"));
    // The known values of today's table, so that a table edit is a conscious one.
    EXPECT_EQ(s.maxIterations, 96);
    EXPECT_EQ(s.hizStartLevel, 1);
}

TEST(ModuleSettings, FromReadsEveryOverride) {
    Settings table(reflections::settingsTable());
    table.assign("reflections.max_iterations=7");
    table.assign("reflections.probes=false");
    table.assign("reflections.trace=linear");
    table.assign("reflections.resolution=half");
    table.assign("reflections.glossy=stochastic");
    table.assign("reflections.temporal=true");
    table.assign("reflections.temporal_alpha=0.25");
    auto s = reflections::ReflectionSettings::from(table);
    EXPECT_EQ(s.resolution, reflections::Resolution::Half);
    EXPECT_EQ(s.glossy, reflections::GlossyMode::Stochastic);
    EXPECT_TRUE(s.temporal);
    EXPECT_FLOAT_EQ(s.temporalAlpha, 0.25f);
    EXPECT_EQ(s.maxIterations, 7);
    EXPECT_FALSE(s.probes);
    EXPECT_EQ(s.trace, reflections::TraceMode::Linear);
}

TEST(ModuleSettings, ProbeDefaultsComeFromTheTable) {
    Settings table(probes::settingsTable());
    probes::ProbeSettings s;
    EXPECT_EQ(s.bounces, table.getInt("probes.bounces"));
    EXPECT_EQ(s.prefilterSamples, table.getInt("probes.prefilter_samples"));
    EXPECT_EQ(int(s.debugView), table.getInt("probes.debug_view"));
    EXPECT_EQ(s.bounces, 2);
}

TEST(ModuleSettings, ProbesReadmeCarriesTheGeneratedTable) {
    std::ifstream in(std::string(SPECULUM_SOURCE_DIR) + "/modules/probes/README.md");
    ASSERT_TRUE(in) << "modules/probes/README.md not found";
    std::stringstream readme;
    readme << in.rdbuf();
    std::string table = Settings(probes::settingsTable()).markdownTable();
    EXPECT_NE(readme.str().find(table), std::string::npos)
        << "modules/probes/README.md: the settings table differs from settingsTable(); paste this:\n"
        << table;
}

TEST(ModuleSettings, ModulesRegisterTheirTablesAovsAndDebugViews) {
    app::ModuleInfo r = reflections::moduleInfo();
    EXPECT_EQ(r.name, "reflections");
    EXPECT_EQ(r.settings.size(), reflections::settingsTable().size());
    EXPECT_NE(app::aovProvider({r}, "method"), nullptr);
    EXPECT_EQ(app::aovProvider({r}, "linear"), nullptr) << "linear is the engine's own AOV";
    EXPECT_EQ(app::debugViews(r).front(), "none");
    app::ModuleInfo p = probes::moduleInfo();
    EXPECT_EQ(app::debugViews(p), (std::vector<std::string>{"none", "influence", "winner"}));
    std::vector<SettingDesc> all = app::settingsOf({}, {p, r});
    EXPECT_EQ(all.size(), p.settings.size() + r.settings.size());
    EXPECT_EQ(all.front().name.rfind("probes.", 0), 0u);
}
