#include "speculum/app/output.hpp"

#include "speculum/core.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace speculum::app {
namespace {

// The last step of every write; a folder in the way (out/color.0000.exr/) is the user's doing and
// gets a message, not an internal error.
void renameInto(const fs::path& tmp, const fs::path& file) {
    std::error_code ec;
    fs::rename(tmp, file, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw Error(ExitCode::Failure, file.string() + ": cannot write: " +
                                           (fs::is_directory(file) ? "a folder has that name" : "rename failed"));
    }
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void writeImage(const fs::path& file, const AovImage& image, OIIO::TypeDesc type, uint32_t channels) {
    fs::path tmp = file;
    tmp += ".tmp" + file.extension().string();
    auto out = OIIO::ImageOutput::create(file.string());
    if (!out) throw Error(ExitCode::Failure, file.string() + ": no image writer: " + OIIO::geterror());
    OIIO::ImageSpec spec(int(image.width), int(image.height), int(channels), type);
    std::vector<float> pixels(size_t(image.width) * image.height * channels);
    for (size_t i = 0; i < size_t(image.width) * image.height; ++i)
        for (uint32_t c = 0; c < channels; ++c) pixels[i * channels + c] = image.rgba[i * 4 + c];
    if (!out->open(tmp.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close())
        throw Error(ExitCode::Failure, file.string() + ": cannot write: " + out->geterror());
    renameInto(tmp, file);
}

}  // namespace

void prepareOutputDir(const fs::path& dir) {
    const std::string name = dir.string();
    if (name.empty()) throw argumentError("--out needs a folder name, got \"\"");
    std::error_code ec;
    auto status = fs::status(dir, ec);
    if (fs::exists(status) && !fs::is_directory(status))
        throw argumentError("--out " + name + " exists and is not a folder" +
                            (fs::is_regular_file(status) ? "" : " (a device or other special file)"));
    fs::create_directories(dir, ec);
    if (ec) throw argumentError("--out " + name + ": cannot create the folder: " + ec.message());
    // Root passes access(W_OK) on read-only folders, and a read-only mount fails only on write:
    // write a probe file.
    fs::path probe = dir / (".speculum-write-test." + std::to_string(::getpid()));
    {
        std::ofstream out(probe);
        if (!out) throw argumentError("--out " + name + ": the folder is not writable");
    }
    fs::remove(probe, ec);
}

void writeExr(const fs::path& file, const AovImage& image) {
    writeImage(file, image, OIIO::TypeDesc::FLOAT, std::max(image.channels, 1u) == 2 ? 3 : image.channels);
}

void writePng(const fs::path& file, const AovImage& image) { writeImage(file, image, OIIO::TypeDesc::UINT8, 3); }

void writeAov(const fs::path& dir, const std::string& name, int frame, const AovImage& image) {
    std::ostringstream stem;
    stem << name << "." << std::setw(4) << std::setfill('0') << frame;
    writeExr(dir / (stem.str() + ".exr"), image);
    if (name == "color") writePng(dir / (stem.str() + ".png"), image);
}

void writeText(const fs::path& file, const std::string& text) {
    fs::path tmp = file;
    tmp += ".tmp";
    {
        std::ofstream out(tmp);
        out << text;
        if (!out) throw Error(ExitCode::Failure, file.string() + ": cannot write");
    }
    renameInto(tmp, file);
}

void progress(const std::string& label, size_t done, size_t total) {
    static const bool tty = isatty(2);
    if (tty)
        std::fprintf(stderr, "\r%s: %zu/%zu%s", label.c_str(), done, total, done == total ? "\n" : "");
    else if (done == total || done % std::max<size_t>(1, total / 10) == 0)
        std::fprintf(stderr, "%s: %zu/%zu\n", label.c_str(), done, total);
}

void TimingLog::add(const FrameResult& frame) {
    for (const PassTime& p : frame.passes) {
        if (!passes_.count(p.name)) order_.push_back(p.name);
        passes_[p.name].push_back(p.ms);
    }
    frames_.push_back(frame.frameMs);
    memory_ = frame.memory;
}

double TimingLog::medianFrameMs() const { return median(frames_); }
double TimingLog::medianPassMs(const std::string& pass) const {
    auto it = passes_.find(pass);
    return it == passes_.end() ? 0.0 : median(it->second);
}

nlohmann::json TimingLog::toJson(const std::string& device, uint32_t width, uint32_t height,
                                 uint64_t persistentBytes) const {
    nlohmann::json passes = nlohmann::json::array();
    for (const std::string& name : order_) {
        const auto& v = passes_.at(name);
        passes.push_back({{"name", name},
                          {"median_ms", median(v)},
                          {"min_ms", *std::min_element(v.begin(), v.end())},
                          {"max_ms", *std::max_element(v.begin(), v.end())}});
    }
    nlohmann::json frame = {{"median_ms", median(frames_)}, {"frames", frames_.size()}};
    if (!frames_.empty()) {
        frame["min_ms"] = *std::min_element(frames_.begin(), frames_.end());
        frame["max_ms"] = *std::max_element(frames_.begin(), frames_.end());
    }
    return {{"device", device},
            {"width", width},
            {"height", height},
            {"passes", passes},
            {"frame", frame},
            {"memory",
             {{"transient_peak_bytes_aliased", memory_.transientWithAliasing},
              {"transient_peak_bytes_unaliased", memory_.transientWithoutAliasing},
              {"persistent_bytes", persistentBytes}}}};
}

std::string TimingLog::summary() const {
    std::ostringstream s;
    s << std::fixed << std::setprecision(2);
    for (const std::string& name : order_) s << std::setw(28) << std::left << name << median(passes_.at(name)) << " ms\n";
    s << std::setw(28) << std::left << "frame (median)" << median(frames_) << " ms\n";
    s << "transient memory: " << memory_.transientWithAliasing / 1048576.0 << " MiB aliased, "
      << memory_.transientWithoutAliasing / 1048576.0 << " MiB without aliasing\n";
    return s.str();
}

}  // namespace speculum::app
