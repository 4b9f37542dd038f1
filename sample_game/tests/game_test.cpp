// The rules and the recordings (no device): the checked-in session, replayed through the rules
// alone, hits the partition, collects every gem and wins, the same way twice.
#include "game.hpp"

#include "speculum/core.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace speculum::game {
namespace {

const std::string kRoot = SPECULUM_SOURCE_DIR;

Scene hall() { return loadScene(kRoot + "/assets/scenes/hall_of_mirrors.gltf"); }

TEST(GameRules, HallHasThreeCollectiblesAndTheStartIsOnTheFloor) {
    Scene scene = hall();
    Game game(scene);
    ASSERT_EQ(game.collectibles().size(), 3u);
    EXPECT_EQ(game.collectibles()[0].name, "collectible.0");
    // Two seconds standing still: on the floor (the mirror strip is 4 mm up), not falling through.
    for (int i = 0; i < 40; ++i) game.advance({.dt = 0.05f});
    EXPECT_TRUE(game.player().grounded);
    EXPECT_NEAR(game.player().feet.y, 0.004f, 0.01f);
    EXPECT_EQ(game.taken(), 0);
}

TEST(GameRules, WalkingIntoAGemTakesIt) {
    Scene scene = hall();
    Game game(scene);
    // Face collectible.0 at (-3.5, -2.5) from the start (-3.5, 0.3): straight down -z, yaw 0.
    game.advance({.dt = 0.0f, .dx = game.yaw() / kMouseRadiansPerPixel});
    EXPECT_NEAR(game.yaw(), 0.0f, 1e-4f);
    int frames = 0;
    while (game.taken() == 0 && frames < 100) {
        game.advance({.dt = 0.05f, .keys = kForward});
        ++frames;
    }
    EXPECT_EQ(game.taken(), 1);
    EXPECT_TRUE(game.collectibles()[0].taken);
    // 2.8 m less the reach (0.6 m) at 3 m/s: 0.73 s.
    EXPECT_NEAR(frames * 0.05, 0.73, 0.1);
}

TEST(GameRules, PausedOrWonNothingMoves) {
    Scene scene = hall();
    Game game(scene);
    glm::vec3 before = game.player().feet;
    game.advance({.dt = 0.5f, .keys = kForward}, true);
    EXPECT_EQ(game.player().feet, before);
    EXPECT_EQ(game.time(), 0.0);
}

TEST(GameDynamicResolution, FollowsTheFrameTimeInSteps) {
    // Twice the target's time: pixels halve, the scale drops by sqrt(2) (0.8 -> 0.566 -> 0.55).
    EXPECT_FLOAT_EQ(nextScale(0.8f, 120.0, 60.0), 0.55f);
    // Half the target's time: up by sqrt(2), capped at 1.
    EXPECT_FLOAT_EQ(nextScale(0.5f, 30.0, 60.0), 0.7f);
    EXPECT_FLOAT_EQ(nextScale(0.9f, 10.0, 60.0), 1.0f);
    // Within a step of the target: no resize for noise.
    EXPECT_FLOAT_EQ(nextScale(0.5f, 63.0, 60.0), 0.5f);
    // Never below the floor however slow.
    EXPECT_FLOAT_EQ(nextScale(0.2f, 1000.0, 60.0), 0.15f);
}

TEST(GameRecording, RoundTripsBitForBit) {
    Recording r{"hall_of_mirrors.gltf", 320, 180, "low", {}};
    r.frames = {{0.0412345678f, 17, -123.456f, 0.1f, 0.55f, {}},
                {1.0f / 60.0f, 0, 0.0f, -3.0f, 1.0f, {"reflections.cmos=false", "preset=medium"}}};
    std::filesystem::path file = std::string(SPECULUM_TEST_TMP) + "/game_roundtrip.session";
    std::filesystem::create_directories(file.parent_path());
    writeRecording(file, r);
    Recording back = readRecording(file);
    EXPECT_EQ(back.scene, r.scene);
    EXPECT_EQ(back.width, 320u);
    EXPECT_EQ(back.preset, "low");
    ASSERT_EQ(back.frames.size(), 2u);
    for (size_t i = 0; i < 2; ++i) EXPECT_TRUE(back.frames[i] == r.frames[i]) << "frame " << i;
}

TEST(GameRecording, BadLinesAreBadInput) {
    std::filesystem::path file = std::string(SPECULUM_TEST_TMP) + "/game_bad.session";
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << "speculum-game recording 1\nscene x.gltf\nf 0.05 1 nan 0 1\n";
    try {
        readRecording(file);
        FAIL() << "read";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
    }
}

TEST(GameRecording, TheCheckedInSessionWinsTheSameWayTwice) {
    Recording r = readRecording(kRoot + "/sample_game/tests/data/hall_of_mirrors.session");
    Scene scene = loadScene(kRoot + "/assets/scenes/" + r.scene);
    Game a(scene), b(scene);
    int wonAt = -1;
    for (size_t i = 0; i < r.frames.size(); ++i) {
        Game::Events e = a.advance(r.frames[i]);
        b.advance(r.frames[i]);
        if (e.won) wonAt = int(i);
        // The south wall is at z = 4: the capsule never passes it.
        EXPECT_LE(a.player().feet.z, 4.0f - a.params().radius + 1e-3f) << "frame " << i;
    }
    EXPECT_GE(a.wallHits(), 1);
    EXPECT_EQ(a.taken(), 3);
    EXPECT_TRUE(a.won());
    EXPECT_GT(wonAt, 0);
    EXPECT_LT(wonAt, int(r.frames.size()) - 5) << "the session should show the win screen for a while";
    EXPECT_EQ(a.player().feet, b.player().feet);
    EXPECT_EQ(a.time(), b.time());
    std::cout << "won at frame " << wonAt << " of " << r.frames.size() << " in " << a.time() << " s, "
              << a.wallHits() << " wall hits\n";
}

}  // namespace
}  // namespace speculum::game
