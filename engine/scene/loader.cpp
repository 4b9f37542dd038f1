// loadScene: container -> JSON -> structural validation -> resources -> meshes -> world space.
// Each stage only sees input the previous stages have proven well-formed.
#include "gltf_document.hpp"

namespace speculum {

Scene loadScene(const std::filesystem::path& path) {
    const gltf::Reader r(path.string());
    Scene scene;
    scene.path = path;
    gltf::Container container = gltf::readContainer(path, r);
    scene.document = gltf::parseJson(container.jsonText, r);
    const gltf::Document d = gltf::parseDocument(scene.document, r);
    gltf::parseMaterials(scene, scene.document, d, r);
    gltf::parseNodes(scene, scene.document, d, r);
    gltf::loadResources(scene, path, container, d, r);
    gltf::buildMeshes(scene, d, r);
    gltf::resolveScene(scene, scene.document, d, r);
    // The environment map's header now, so that a bad one fails before any device starts.
    if (std::filesystem::path env = environmentPath(scene); !env.empty()) {
        try {
            checkEnvironmentImage(env);
        } catch (const Error& e) {
            r.fail("scenes[].extras.environment", e.what());
        }
    }
    return scene;
}

MaterialReflections reflectionsOf(const Material& material) {
    MaterialReflections r = material.reflections.value_or(MaterialReflections{});
    if (material.unlit) r.mode = ReflectionMode::Off;
    return r;
}

bool reflects(const Material& material) {
    return reflectionsOf(material).mode != ReflectionMode::Off;
}

const Camera* Scene::findCamera(const std::string& name) const {
    for (const Camera& c : cameras)
        if (c.name == name) return &c;
    return nullptr;
}

}  // namespace speculum
