#include "game.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace speculum::game {

namespace {

constexpr const char* kMagic = "speculum-game recording 1";

bool isCollectible(const std::string& name) { return name.rfind("collectible.", 0) == 0; }

}  // namespace

Recording readRecording(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in || std::filesystem::is_directory(file)) throw inputError(file.string(), "cannot read the recording");
    Recording r;
    std::string line;
    int number = 0;
    std::vector<std::string> sets;  // `s` lines waiting for their frame
    auto fail = [&](const std::string& why) {
        throw inputError(file.string(), "line " + std::to_string(number) + ": " + why);
    };
    while (std::getline(in, line)) {
        ++number;
        if (number == 1) {
            if (line != kMagic) fail(std::string("expected '") + kMagic + "'");
            continue;
        }
        std::istringstream s(line);
        std::string key;
        if (!(s >> key) || key[0] == '#') continue;
        if (key == "scene") {
            if (!(s >> r.scene)) fail("scene: expected a file name");
        } else if (key == "size") {
            std::string wh;
            if (!(s >> wh) || std::sscanf(wh.c_str(), "%ux%u", &r.width, &r.height) != 2 || r.width < 16 ||
                r.height < 16 || r.width > 8192 || r.height > 8192)
                fail("size: expected WxH between 16 and 8192");
        } else if (key == "preset") {
            if (!(s >> r.preset)) fail("preset: expected a name");
        } else if (key == "s") {
            std::string kv;
            if (!(s >> kv) || kv.find('=') == std::string::npos) fail("s: expected KEY=VALUE");
            sets.push_back(kv);
        } else if (key == "f") {
            FrameInput f;
            if (!(s >> f.dt >> f.keys >> f.dx >> f.dy >> f.scale)) fail("f: expected dt keys dx dy scale");
            f.sets = std::move(sets);
            sets.clear();
            if (!std::isfinite(f.dt) || f.dt < 0.0f || f.dt > 1.0f) fail("f: dt must be in [0, 1] s");
            if (!std::isfinite(f.dx) || !std::isfinite(f.dy)) fail("f: mouse motion must be finite");
            if (!(f.scale >= 0.1f && f.scale <= 1.0f)) fail("f: scale must be in [0.1, 1]");
            r.frames.push_back(f);
        } else {
            fail("unknown key '" + key + "'");
        }
    }
    if (number == 0) throw inputError(file.string(), "empty recording");
    if (r.frames.empty()) throw inputError(file.string(), "no frames");
    return r;
}

void writeRecording(const std::filesystem::path& file, const Recording& r) {
    std::ofstream out(file);
    if (!out) throw inputError(file.string(), "cannot write the recording");
    out << kMagic << "\n"
        << "# f dt(s) keys(1 W, 2 S, 4 A, 8 D, 16 space) mouse-dx mouse-dy(px) internal-scale\n"
        << "# s KEY=VALUE: a setting the HUD changed, from the next f line's frame on\n"
        << "scene " << r.scene << "\nsize " << r.width << "x" << r.height << "\npreset " << r.preset << "\n";
    char buf[128];
    for (const FrameInput& f : r.frames) {
        for (const std::string& kv : f.sets) out << "s " << kv << "\n";
        // %.9g: floats survive the round trip bit for bit.
        std::snprintf(buf, sizeof buf, "f %.9g %u %.9g %.9g %.9g\n", f.dt, f.keys, f.dx, f.dy, f.scale);
        out << buf;
    }
}

float nextScale(float scale, double frameMs, double targetMs, float minScale, float step) {
    float wanted = scale * float(std::sqrt(targetMs / std::max(1.0, frameMs)));
    wanted = std::clamp(std::round(wanted / step) * step, minScale, 1.0f);
    return std::abs(wanted - scale) >= step - 1e-4f ? wanted : scale;
}

Game::Game(const Scene& scene, const PlayerParams& params) : params_(params) {
    level_ = levelFromScene(scene, [&](int node) { return node < 0 || !isCollectible(scene.nodes[size_t(node)].name); });
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (isCollectible(scene.nodes[i].name))
            collectibles_.push_back({int(i), scene.nodes[i].name, glm::vec3(scene.nodes[i].world[3])});
    std::sort(collectibles_.begin(), collectibles_.end(),
              [](const Collectible& a, const Collectible& b) { return a.name < b.name; });
    const Camera* start = scene.findCamera("main");
    if (!start && !scene.cameras.empty()) start = &scene.cameras.front();
    glm::vec3 eye = start ? glm::vec3(start->world[3]) : 0.5f * (scene.boundsMin + scene.boundsMax);
    glm::vec3 dir = start ? -glm::normalize(glm::vec3(start->world[2])) : glm::vec3(0, 0, -1);
    player_.feet = eye - glm::vec3(0.0f, params_.eyeHeight, 0.0f);
    yaw_ = std::atan2(-dir.x, -dir.z);
    pitch_ = std::asin(std::clamp(dir.y, -1.0f, 1.0f));
}

glm::vec3 Game::forward() const {
    return {-std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_), -std::cos(yaw_) * std::cos(pitch_)};
}

int Game::taken() const {
    return int(std::count_if(collectibles_.begin(), collectibles_.end(), [](const Collectible& c) { return c.taken; }));
}

Game::Events Game::advance(const FrameInput& in, bool paused) {
    Events events;
    if (paused || won_) return events;
    yaw_ -= in.dx * kMouseRadiansPerPixel;
    pitch_ = std::clamp(pitch_ - in.dy * kMouseRadiansPerPixel, -1.4f, 1.4f);
    MoveInput move;
    move.yaw = yaw_;
    move.move.y = float((in.keys & kForward) != 0) - float((in.keys & kBack) != 0);
    move.move.x = float((in.keys & kRight) != 0) - float((in.keys & kLeft) != 0);
    move.jump = (in.keys & kJump) != 0;
    owed_ += double(in.dt);
    while (owed_ >= double(kStep) && !won_) {
        owed_ -= double(kStep);
        time_ += double(kStep);
        StepEvents e = step(level_, params_, player_, move);
        // A wall hit counts once per contact, not once per step against it.
        if (e.hitWall && !touchingWall_) {
            events.hitWall = true;
            ++wallHits_;
        }
        touchingWall_ = e.hitWall;
        for (size_t i = 0; i < collectibles_.size(); ++i) {
            Collectible& c = collectibles_[i];
            glm::vec2 d(c.position.x - player_.feet.x, c.position.z - player_.feet.z);
            bool reach = glm::length(d) < params_.radius + 0.3f && c.position.y > player_.feet.y - 0.3f &&
                         c.position.y < player_.feet.y + params_.height + 0.3f;
            if (!c.taken && reach) {
                c.taken = true;
                events.collected.push_back(int(i));
            }
        }
        if (!collectibles_.empty() && taken() == int(collectibles_.size())) {
            won_ = true;
            events.won = true;
        }
    }
    return events;
}

}  // namespace speculum::game
