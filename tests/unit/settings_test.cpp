#include "speculum/core.hpp"
#include "speculum/settings.hpp"

#include <gtest/gtest.h>

using namespace speculum;

namespace {
Settings makeTable() {
    return Settings({
        {"render.exposure", SettingType::Float, "EV", 0.01, 100.0, 1.0, {}, "exposure"},
        {"render.shadow_map_size", SettingType::Int, "px", 16, 8192, 2048, {}, "shadow map size"},
        {"render.shadows", SettingType::Bool, "", 0, 1, 1, {}, "shadows"},
        {"reflections.trace", SettingType::Enum, "", 0, 1, 1, {"linear", "hiz"}, "trace mode"},
    });
}
}  // namespace

TEST(Settings, DefaultsAndAssign) {
    Settings s = makeTable();
    EXPECT_DOUBLE_EQ(s.get("render.exposure"), 1.0);
    EXPECT_EQ(s.getChoice("reflections.trace"), "hiz");
    s.assign("render.exposure=2.5");
    s.assign("reflections.trace=linear");
    s.assign("render.shadows=false");
    EXPECT_FLOAT_EQ(s.getFloat("render.exposure"), 2.5f);
    EXPECT_EQ(s.getChoice("reflections.trace"), "linear");
    EXPECT_FALSE(s.getBool("render.shadows"));
}

TEST(Settings, UnknownKeyAndBadValuesAreArgumentErrors) {
    Settings s = makeTable();
    for (const char* bad : {"render.nope=1", "render.exposure=abc", "render.exposure=1000",
                            "render.shadow_map_size=12.5", "reflections.trace=cone", "noequals"}) {
        try {
            s.assign(bad);
            FAIL() << bad << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadArguments) << bad;
        }
    }
}

TEST(Settings, JsonRoundTrip) {
    Settings a = makeTable();
    a.assign("render.exposure=0.5");
    a.assign("reflections.trace=linear");
    Settings b = makeTable();
    b.fromJson(a.toJson(), "mem");
    EXPECT_EQ(a.toJson(), b.toJson());
    EXPECT_NE(a.markdownTable().find("`render.shadow_map_size` | px"), std::string::npos);
}

TEST(Settings, BadJsonNamesTheSource) {
    Settings s = makeTable();
    try {
        s.fromJson(nlohmann::json{{"render.bogus", 1}}, "my_settings.json");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("my_settings.json"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("render.bogus"), std::string::npos);
    }
}
