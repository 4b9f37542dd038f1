// Issue 15's limits without a device: JSON depth, strict settings values, the environment
// map's header and the expanded geometry, each one Error naming the file.
#include "scene_test_support.hpp"

#include "speculum/core.hpp"
#include "speculum/limits.hpp"
#include "speculum/settings.hpp"

#include <gtest/gtest.h>

#include <fstream>

using namespace speculum;
using namespace speculum::scenetest;

namespace {

std::string nest(int depth) {
    return std::string(size_t(depth), '[') + "0" + std::string(size_t(depth), ']');
}

ExitCode codeOf(const std::function<void()>& f, std::string* message = nullptr) {
    try {
        f();
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.code();
    }
    return ExitCode::Ok;
}

}  // namespace

TEST(Limits, JsonDepthCountsBracketsOutsideStrings) {
    EXPECT_EQ(codeOf([] { limits::checkJsonDepth(nest(limits::kMaxJsonDepth), "f.json"); }), ExitCode::Ok);
    std::string msg;
    EXPECT_EQ(codeOf([] { limits::checkJsonDepth(nest(limits::kMaxJsonDepth + 1), "f.json"); }, &msg),
              ExitCode::BadInput);
    EXPECT_NE(msg.find("f.json: JSON nests deeper than 512"), std::string::npos) << msg;
    // Brackets inside strings, escaped quotes included, are text.
    std::string text = "{\"a\": \"" + std::string(2000, '[') + "\\\"[[[\"}";
    EXPECT_EQ(codeOf([&] { limits::checkJsonDepth(text, "s.json"); }), ExitCode::Ok);
}

TEST(Limits, SettingsValuesMatchTheirType) {
    Settings s({{"a.x", SettingType::Float, "", 0, 100, 1, {}, ""},
                {"a.mode", SettingType::Enum, "", 0, 1, 0, {"one", "two"}, ""},
                {"a.on", SettingType::Bool, "", 0, 1, 1, {}, ""}});
    for (const char* bad : {"0x10", " 5", "5 ", "inf", "nan", "1e", ""})
        EXPECT_EQ(codeOf([&] { s.set("a.x", std::string(bad)); }), ExitCode::BadArguments) << bad;
    s.set("a.x", std::string("2.5e1"));
    EXPECT_EQ(s.get("a.x"), 25.0);
    EXPECT_EQ(codeOf([&] { s.fromJson(nlohmann::json{{"a.mode", true}}, "s.json"); }), ExitCode::BadInput);
    EXPECT_EQ(codeOf([&] { s.fromJson(nlohmann::json{{"a.on", 1}}, "s.json"); }), ExitCode::BadInput);
    EXPECT_EQ(codeOf([&] { s.fromJson(nlohmann::json{{"a.x", "3"}}, "s.json"); }), ExitCode::BadInput);
    s.fromJson(nlohmann::json{{"a.mode", "two"}, {"a.on", false}, {"a.x", 3}}, "s.json");
    EXPECT_EQ(s.getChoice("a.mode"), "two");
}

TEST(Limits, SettingsFilesAreRegularAndEndAfterTheObject) {
    auto dir = tmpDir("limits_settings");
    Settings s({{"a.x", SettingType::Float, "", 0, 100, 1, {}, ""}});
    std::string msg;
    EXPECT_EQ(codeOf([&] { s.load(dir); }, &msg), ExitCode::BadInput);
    EXPECT_NE(msg.find("is a folder"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { s.load("/dev/zero"); }, &msg), ExitCode::BadInput);
    EXPECT_NE(msg.find("/dev/zero: is not a regular file"), std::string::npos) << msg;
    std::ofstream(dir / "trailing.json") << "{\"a.x\": 2} {}";
    EXPECT_EQ(codeOf([&] { s.load(dir / "trailing.json"); }, &msg), ExitCode::BadInput);
    EXPECT_NE(msg.find("trailing.json"), std::string::npos) << msg;
}

TEST(Limits, EnvironmentHeaderClaimingHugeSizeIsRefusedBeforeReading) {
    auto dir = tmpDir("limits_env");
    std::ofstream(dir / "huge.ppm", std::ios::binary) << "P6\n100000 100000\n255\n";
    std::string msg;
    EXPECT_EQ(codeOf([&] { checkEnvironmentImage(dir / "huge.ppm"); }, &msg), ExitCode::BadInput);
    EXPECT_NE(msg.find("huge.ppm: environment map header claims 100000x100000"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { checkEnvironmentImage("/dev/urandom"); }, &msg), ExitCode::BadInput);
    EXPECT_NE(msg.find("not a regular file"), std::string::npos) << msg;
    std::ofstream(dir / "small.ppm", std::ios::binary) << "P6\n2 1\n255\n" << std::string(6, '\x7f');
    EXPECT_EQ(codeOf([&] { checkEnvironmentImage(dir / "small.ppm"); }), ExitCode::Ok);
}

TEST(Limits, ReusedAccessorsCountOncePerPrimitive) {
    auto dir = tmpDir("limits_geometry");
    GltfData g = quad();
    // 2^23 primitives' worth of the quad's 4 vertices would be tiny; reuse needs a big accessor:
    // claim 2^24 vertices through a sparse accessor with no buffer view (all zeros).
    g.doc["accessors"].push_back({{"componentType", 5126}, {"count", 1 << 24}, {"type", "VEC3"}});
    json prim = {{"attributes", {{"POSITION", g.doc["accessors"].size() - 1}}}};
    g.doc["meshes"][0]["primitives"] = json::array();
    for (int i = 0; i < 2; ++i) g.doc["meshes"][0]["primitives"].push_back(prim);
    std::string msg;
    EXPECT_EQ(codeOf([&] { loadScene(writeGltf(dir / "zeros.gltf", g)); }, &msg), ExitCode::BadInput);
    EXPECT_NE(msg.find("zeros.gltf: meshes: the primitives expand to 33554432 vertices"), std::string::npos) << msg;
}
