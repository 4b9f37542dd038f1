#include "speculum/app/camera_path.hpp"

#include "speculum/core.hpp"
#include "speculum/limits.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace speculum::app {
namespace {

glm::vec3 readVec3(const nlohmann::json& j, const std::string& file, const std::string& what) {
    if (!j.is_array() || j.size() != 3) throw inputError(file, what + " must be an array of 3 numbers");
    glm::vec3 v;
    for (int i = 0; i < 3; ++i) {
        if (!j[i].is_number()) throw inputError(file, what + " must be an array of 3 numbers");
        v[i] = j[i].get<float>();
        if (!std::isfinite(v[i])) throw inputError(file, what + " is not finite");
    }
    return v;
}

}  // namespace

std::vector<CameraPose> loadCameraPath(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::string text = limits::readJsonText(path, "camera path");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw inputError(file, std::string("not valid JSON: ") + e.what());
    }
    if (!j.is_object()) throw inputError(file, "a camera path must be a JSON object");
    if (!j.contains("frames") || !j["frames"].is_number_integer())
        throw inputError(file, "\"frames\" must be an integer");
    int frames = j["frames"].get<int>();
    if (frames < 1 || frames > 100000) throw inputError(file, "\"frames\" must be in 1..100000");
    float fov = j.value("fov_deg", 55.0f);
    if (!(fov > 1.0f && fov < 179.0f)) throw inputError(file, "\"fov_deg\" must be in 1..179");
    if (!j.contains("keys") || !j["keys"].is_array() || j["keys"].empty())
        throw inputError(file, "\"keys\" must be a non-empty array");
    std::vector<CameraPose> keys;
    for (size_t k = 0; k < j["keys"].size(); ++k) {
        const auto& key = j["keys"][k];
        std::string where = "keys[" + std::to_string(k) + "]";
        if (!key.is_object()) throw inputError(file, where + " must be an object");
        CameraPose pose;
        pose.eye = readVec3(key.value("eye", nlohmann::json()), file, where + ".eye");
        pose.target = readVec3(key.value("target", nlohmann::json()), file, where + ".target");
        if (key.contains("up")) pose.up = readVec3(key["up"], file, where + ".up");
        if (glm::length(pose.target - pose.eye) < 1e-6f) throw inputError(file, where + ": eye equals target");
        pose.fovDeg = fov;
        keys.push_back(pose);
    }
    std::vector<CameraPose> out;
    for (int i = 0; i < frames; ++i) {
        float t = frames == 1 ? 0.0f : float(i) / float(frames - 1) * float(keys.size() - 1);
        size_t a = std::min(static_cast<size_t>(t), keys.size() - 1);
        size_t b = std::min(a + 1, keys.size() - 1);
        float f = t - float(a);
        CameraPose p = keys[a];
        p.eye = glm::mix(keys[a].eye, keys[b].eye, f);
        p.target = glm::mix(keys[a].target, keys[b].target, f);
        p.up = glm::normalize(glm::mix(keys[a].up, keys[b].up, f));
        out.push_back(p);
    }
    return out;
}

}  // namespace speculum::app
