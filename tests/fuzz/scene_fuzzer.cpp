// libFuzzer target for the scene loader (optional build: -DSPECULUM_FUZZ=ON with clang; see
// tests/fuzz/README.md). The loader takes a path, so each input is written to a file in a
// per-process folder beside a link to the corpus's environment maps. Every speculum::Error is an
// accepted outcome (a clean exit 3 in the tools); anything else -- another exception, a crash,
// an AddressSanitizer or UBSan report, a leak -- is a finding.
#include "speculum/core.hpp"
#include "speculum/scene.hpp"

#include <unistd.h>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

std::filesystem::path inputPath() {
    static const std::filesystem::path path = [] {
        std::filesystem::path dir =
            std::filesystem::temp_directory_path() / ("speculum-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir / "scenes");
        // SPECULUM_FUZZ_ASSETS=assets: the scenes' .bin files beside the input and ../env, so
        // mutants of the real scenes reach buffers, meshes and the environment check.
        if (const char* assets = std::getenv("SPECULUM_FUZZ_ASSETS")) {
            std::error_code ec;
            for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(assets) / "scenes", ec))
                std::filesystem::create_symlink(e.path(), dir / "scenes" / e.path().filename(), ec);
            std::filesystem::create_directory_symlink(std::filesystem::path(assets) / "env", dir / "env", ec);
        }
        return dir / "scenes" / "input.gltf";
    }();
    return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::filesystem::path path = inputPath();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    speculum::setLogLevel(speculum::LogLevel::Error);  // placeholder warnings would flood the log
    try {
        speculum::Scene scene = speculum::loadScene(path);
        (void)speculum::sceneBytes(scene);
    } catch (const speculum::Error&) {
    }
    return 0;
}
