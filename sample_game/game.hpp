// The game's rules and its recordings, on the CPU: a player walking a level (player.hpp), the
// collectibles (nodes named `collectible.N`), a timer and the win; one FrameInput per rendered
// frame drives it, so a recording of those inputs replays the same session (the fixed step runs
// as many times as the recorded frame times add up to).
#pragma once

#include "player.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace speculum::game {

enum Key : uint32_t { kForward = 1, kBack = 2, kLeft = 4, kRight = 8, kJump = 16 };

// What one frame gave the game: its time, the held keys, the mouse's motion (pixels), and the
// internal resolution's scale the frame rendered at (so that a replay renders the same sizes).
struct FrameInput {
    float dt = 0.0f;
    uint32_t keys = 0;
    float dx = 0.0f, dy = 0.0f;
    float scale = 1.0f;
    // Settings the HUD changed this frame, before it rendered ("KEY=VALUE"; "preset=NAME" loads a
    // preset): recorded as `s` lines before the frame's `f` line.
    std::vector<std::string> sets;

    // Exact: a recording must replay the frames bit for bit.
    bool operator==(const FrameInput&) const = default;
};

struct Recording {
    std::string scene;  // file name under assets/scenes, or a path
    uint32_t width = 320, height = 180;
    std::string preset = "low";
    std::vector<FrameInput> frames;
};
// Text, one line per frame (sample_game/README.md). Throws Error(BadInput) naming the file and line.
Recording readRecording(const std::filesystem::path& file);
void writeRecording(const std::filesystem::path& file, const Recording& recording);

struct Collectible {
    int node = -1;
    std::string name;
    glm::vec3 position{0.0f};
    bool taken = false;
};

inline constexpr float kMouseRadiansPerPixel = 0.0025f;

// The dynamic resolution's next scale of the window for the internal image: the scale moves by
// the square root of target / frame time (pixels go with its square), rounded to `step` and kept in
// [minScale, 1]; it changes only by at least one step, so the graph's images are not resized for
// noise.
float nextScale(float scale, double frameMs, double targetMs, float minScale = 0.15f, float step = 0.05f);

class Game {
public:
    // The level is every mesh but the collectibles; the player starts at the camera `main` (or
    // the first camera), on its feet below the eye.
    explicit Game(const Scene& scene, const PlayerParams& params = {});

    struct Events {
        std::vector<int> collected;  // indices into collectibles()
        bool hitWall = false;
        bool won = false;  // this frame
    };
    // Look, then as many fixed steps as the time owed holds; nothing moves once won or while paused.
    Events advance(const FrameInput& input, bool paused = false);

    const Player& player() const { return player_; }
    const PlayerParams& params() const { return params_; }
    glm::vec3 eye() const { return player_.eye(params_); }
    glm::vec3 forward() const;
    float yaw() const { return yaw_; }
    float pitch() const { return pitch_; }
    const std::vector<Collectible>& collectibles() const { return collectibles_; }
    int taken() const;
    bool won() const { return won_; }
    double time() const { return time_; }  // simulated seconds until the win
    int wallHits() const { return wallHits_; }
    const Level& level() const { return level_; }

private:
    PlayerParams params_;
    Level level_;
    Player player_;
    std::vector<Collectible> collectibles_;
    float yaw_ = 0.0f, pitch_ = 0.0f;
    double owed_ = 0.0;
    double time_ = 0.0;
    bool won_ = false;
    bool touchingWall_ = false;
    int wallHits_ = 0;
};

}  // namespace speculum::game
