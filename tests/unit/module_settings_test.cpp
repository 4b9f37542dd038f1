// Every setting is described once: a table row names the setting and binds the struct field it
// fills, and the struct takes its defaults from the rows. These fail where a row fills the wrong
// field or none, a field is bound by no row, a default differs from the table (a default written
// twice drifts: the struct once said max_iterations 64 and hiz_start_level 2 while the table said
// 96 and 1), or a README's table differs from the code's.
#include "speculum/app/engine_settings.hpp"
#include "speculum/probes/probes.hpp"
#include "speculum/reflections/reflections.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <new>
#include <sstream>

#include <gtest/gtest.h>

using namespace speculum;

namespace {

// A value of the setting in its range that is not its default.
double otherValue(const SettingDesc& d) {
    if (d.type == SettingType::Bool || d.type == SettingType::Enum) return d.defaultValue == 0.0 ? 1.0 : 0.0;
    return d.defaultValue != d.max ? d.max : d.min;
}

bool near(double a, double b) { return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b)); }

// Each row's field holds the table's default, and a Settings with only that row's value changed
// fills a struct that differs from the defaults in that field and no other.
template <class S>
void expectEachRowFillsItsOwnField() {
    const S defaults;
    const std::vector<SettingField<S>>& rows = S::fields().rows();
    ASSERT_FALSE(rows.empty());
    for (size_t i = 0; i < rows.size(); ++i) {
        const SettingDesc& d = rows[i].desc;
        EXPECT_TRUE(near(rows[i].read(defaults), d.defaultValue)) << d.name << ": the struct's default is not the table's";
        Settings settings(S::fields().descs());
        double changed = otherValue(d);
        settings.set(d.name, changed);
        S filled = fromSettings<S>(settings);
        EXPECT_TRUE(near(rows[i].read(filled), changed)) << d.name << " does not reach its field";
        for (size_t j = 0; j < rows.size(); ++j) {
            if (j != i)
                EXPECT_EQ(rows[j].read(filled), rows[j].read(defaults))
                    << d.name << " also wrote the field of " << rows[j].desc.name;
        }
    }
}

// A field no row binds keeps whatever bytes lay under it: built over zeros and over ones, the two
// structs then differ (the structs have no other constructor that could write it).
template <class S>
void expectTheTableWritesEveryField() {
    alignas(S) unsigned char zeros[sizeof(S)];
    alignas(S) unsigned char ones[sizeof(S)];
    std::memset(zeros, 0x00, sizeof(S));
    std::memset(ones, 0xff, sizeof(S));
    const S* a = new (zeros) S();
    const S* b = new (ones) S();
    EXPECT_TRUE(*a == *b) << "a field is bound by no row of the table";
    static_assert(std::is_trivially_destructible_v<S>);
}

void expectReadmeCarries(const std::string& readme, const std::vector<SettingDesc>& descs) {
    std::ifstream in(std::string(SPECULUM_SOURCE_DIR) + "/" + readme);
    ASSERT_TRUE(in) << readme << " not found";
    std::stringstream text;
    text << in.rdbuf();
    std::string table = Settings(descs).markdownTable();
    EXPECT_NE(text.str().find(table), std::string::npos)
        << readme << ": the settings table differs from the code's; paste this:\n" << table;
}

}  // namespace

TEST(ModuleSettings, ReflectionRowsFillTheirOwnFields) {
    expectEachRowFillsItsOwnField<reflections::ReflectionSettings>();
    expectTheTableWritesEveryField<reflections::ReflectionSettings>();
    EXPECT_EQ(reflections::settingsTable().size(), reflections::ReflectionSettings::fields().rows().size());
}

TEST(ModuleSettings, ReflectionDefaultsComeFromTheTable) {
    reflections::ReflectionSettings s;
    // The known values of today's table, so that a table edit is a conscious one.
    EXPECT_EQ(s.maxIterations, 96);
    EXPECT_EQ(s.hizStartLevel, 1);
    EXPECT_FALSE(s.cmoPassBehind);
}

TEST(ModuleSettings, FromSettingsReadsEveryOverride) {
    Settings table(reflections::settingsTable());
    table.assign("reflections.max_iterations=7");
    table.assign("reflections.probes=false");
    table.assign("reflections.trace=linear");
    table.assign("reflections.resolution=half");
    table.assign("reflections.glossy=stochastic");
    table.assign("reflections.temporal=true");
    table.assign("reflections.temporal_alpha=0.25");
    table.assign("reflections.cmo_unresolved=pass_behind");
    auto s = fromSettings<reflections::ReflectionSettings>(table);
    EXPECT_EQ(s.resolution, reflections::Resolution::Half);
    EXPECT_EQ(s.glossy, reflections::GlossyMode::Stochastic);
    EXPECT_TRUE(s.temporal);
    EXPECT_FLOAT_EQ(s.temporalAlpha, 0.25f);
    EXPECT_EQ(s.maxIterations, 7);
    EXPECT_FALSE(s.probes);
    EXPECT_EQ(s.trace, reflections::TraceMode::Linear);
    EXPECT_TRUE(s.cmoPassBehind);
}

TEST(ModuleSettings, ProbeRowsFillTheirOwnFields) {
    expectEachRowFillsItsOwnField<probes::ProbeSettings>();
    expectTheTableWritesEveryField<probes::ProbeSettings>();
    EXPECT_EQ(probes::ProbeSettings().bounces, 2);
}

TEST(ModuleSettings, RenderRowsFillTheirOwnFields) {
    expectEachRowFillsItsOwnField<render::RendererOptions>();
    expectEachRowFillsItsOwnField<render::EnvironmentOptions>();
    std::vector<std::string> names;
    for (const SettingDesc& d : app::engineSettingsTable()) names.push_back(d.name);
    EXPECT_EQ(names, (std::vector<std::string>{"render.exposure", "render.shadow_map_size", "render.environment_size",
                                               "render.environment_samples"}));
    // Designated initializers keep the table's defaults for the fields they leave out.
    render::EnvironmentOptions e{.cubeSize = 8};
    EXPECT_EQ(e.prefilterSamples, 64u);
    EXPECT_EQ(render::RendererOptions().shadowMapSize, 2048u);
}

TEST(ModuleSettings, ARowOfAnotherTypeIsALogicError) {
    struct Mixed {
        int count = 0;
    };
    EXPECT_THROW(bind<&Mixed::count>({"x.count", SettingType::Float, "", 0, 1, 0, {}, ""}), std::logic_error);
    EXPECT_NO_THROW(bind<&Mixed::count>({"x.count", SettingType::Int, "", 0, 1, 0, {}, ""}));
}

TEST(ModuleSettings, ProbesReadmeCarriesTheGeneratedTable) {
    expectReadmeCarries("modules/probes/README.md", probes::settingsTable());
}

// A changed default or range that is not in the README fails here.
TEST(ReflectionsSettings, ReadmeCarriesTheGeneratedTable) {
    expectReadmeCarries("modules/reflections/README.md", reflections::settingsTable());
}

TEST(EngineSettings, ReadmeCarriesTheGeneratedTable) { expectReadmeCarries("README.md", app::engineSettingsTable()); }

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
