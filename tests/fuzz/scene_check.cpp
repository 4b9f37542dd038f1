// speculum-scene-check --scene FILE [--scene FILE]...: loads each scene as every tool does
// (container, JSON depth, structure, buffers, images, expanded geometry, the environment map's
// header), without a device. For each file it prints the loader's message (or a summary) and
// then a line "@@ exit N" with the status a tool would return for it (0 or 3); the process
// exits with the last file's status, 2 for bad arguments. Several files per process spare the
// fuzzer the libraries' start-up (0.2 s of CPU each); tests/fuzz/README.md.
#include "speculum/core.hpp"
#include "speculum/scene.hpp"

#include <cstdio>
#include <cstring>
#include <vector>

namespace {

int check(const char* path) {
    try {
        speculum::Scene scene = speculum::loadScene(path);
        speculum::SceneBytes b = speculum::sceneBytes(scene);
        std::printf("%s: %zu meshes, %zu images, %zu instances, %llu bytes for the device\n", path, scene.meshes.size(),
                    scene.images.size(), scene.instances.size(), static_cast<unsigned long long>(b.total()));
        return 0;
    } catch (const speculum::Error& e) {
        std::printf("speculum-scene-check: %s\n", e.what());
        return static_cast<int>(e.code());
    } catch (const std::exception& e) {
        std::printf("speculum-scene-check: internal error: %s\n", e.what());
        return static_cast<int>(speculum::ExitCode::Failure);
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<const char*> files;
    for (int i = 1; i + 1 < argc && std::strcmp(argv[i], "--scene") == 0; i += 2) files.push_back(argv[i + 1]);
    if (files.empty() || argc != int(1 + 2 * files.size())) {
        std::fprintf(stderr, "usage: speculum-scene-check --scene FILE [--scene FILE]...\n");
        return static_cast<int>(speculum::ExitCode::BadArguments);
    }
    int code = 0;
    for (const char* f : files) {
        std::fflush(stderr);  // warnings go to stderr; keep them before the marker
        code = check(f);
        std::printf("@@ exit %d\n", code);
        std::fflush(stdout);
    }
    return code;
}
