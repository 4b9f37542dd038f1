// Checks of what a scene asks for that go beyond its JSON: the environment map's header and the
// bytes its geometry and textures will take on the device (speculum/limits.hpp).
#include "speculum/limits.hpp"
#include "speculum/scene.hpp"

#include "speculum/core.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>

namespace speculum {

std::filesystem::path environmentPath(const Scene& scene) {
    const nlohmann::json& doc = scene.document;
    if (!doc.is_object() || !doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty()) return {};
    size_t index = 0;
    if (doc.contains("scene") && doc["scene"].is_number_unsigned()) index = doc["scene"].get<size_t>();
    if (index >= doc["scenes"].size()) return {};
    const nlohmann::json& s = doc["scenes"][index];
    if (!s.is_object() || !s.contains("extras") || !s["extras"].is_object() || !s["extras"].contains("environment"))
        return {};
    const nlohmann::json& env = s["extras"]["environment"];
    if (!env.is_string() || env.get<std::string>().empty())
        throw inputError(scene.path.string(),
                         "scenes[" + std::to_string(index) + "].extras.environment must be a non-empty path string");
    return scene.path.parent_path() / env.get<std::string>();
}

void checkEnvironmentImage(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) throw inputError(file, "environment map: no such file");
    if (!std::filesystem::is_regular_file(status))
        throw inputError(file, "environment map: not a regular file (a folder or a device cannot be an image)");
    auto in = OIIO::ImageInput::open(file);
    if (!in) {
        std::string why = OIIO::geterror();
        throw inputError(file, "environment map: not an image OpenImageIO can read" + (why.empty() ? "" : ": " + why));
    }
    const OIIO::ImageSpec& spec = in->spec();
    uint64_t w = uint64_t(std::max(spec.width, 0)), h = uint64_t(std::max(spec.height, 0));
    if (w == 0 || h == 0 || spec.nchannels <= 0) throw inputError(file, "environment map has no pixels");
    if (w > limits::kMaxEnvironmentSide || h > limits::kMaxEnvironmentSide || w * h > limits::kMaxEnvironmentPixels)
        throw inputError(file, "environment map header claims " + std::to_string(w) + "x" + std::to_string(h) +
                                   " pixels; the limit is " + std::to_string(limits::kMaxEnvironmentSide) +
                                   " a side and " + std::to_string(limits::kMaxEnvironmentPixels) +
                                   " pixels (8192x4096)");
}

SceneBytes sceneBytes(const Scene& scene) {
    SceneBytes b;
    for (const Mesh& m : scene.meshes)
        for (const Primitive& p : m.primitives) {
            b.vertices += p.vertices.size() * sizeof(Vertex);
            b.indices += p.indices.size() * sizeof(uint32_t);
        }
    for (const Image& img : scene.images)
        b.textures += uint64_t(img.width) * img.height * 4 * 4 / 3;  // RGBA8 plus the mip chain
    return b;
}

}  // namespace speculum
