// Writing what a run produces: AOV images (EXR, PNG), timings.json, progress lines.
#pragma once

#include "speculum/app/frame_runner.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace speculum::app {

// Makes --out DIR ready before any device starts: creates it (and its parents) and proves it
// writable with a probe file. Throws Error(BadArguments) naming the path for "" , an existing
// file, a device (/dev/null), a path under a file, or a folder that cannot be written.
void prepareOutputDir(const std::filesystem::path& dir);

// NAME.FFFF.exr (linear float, the AOV's channels); `color` also as NAME.FFFF.png (8-bit sRGB).
void writeAov(const std::filesystem::path& dir, const std::string& name, int frame, const AovImage& image);
void writeExr(const std::filesystem::path& file, const AovImage& image);
void writePng(const std::filesystem::path& file, const AovImage& image);
// Writes to a temporary file in the same folder, then renames.
void writeText(const std::filesystem::path& file, const std::string& text);

// Prints "label: i/n" on one line of stderr (rewritten in place on a terminal).
void progress(const std::string& label, size_t done, size_t total);

// Per-pass GPU times over counted frames: median, min, max.
class TimingLog {
public:
    void add(const FrameResult& frame);
    nlohmann::json toJson(const std::string& device, uint32_t width, uint32_t height, uint64_t persistentBytes) const;
    std::string summary() const;  // human-readable table
    double medianFrameMs() const;
    double medianPassMs(const std::string& pass) const;

private:
    std::vector<std::string> order_;
    std::map<std::string, std::vector<double>> passes_;
    std::vector<double> frames_;
    MemoryStats memory_;
};

}  // namespace speculum::app
