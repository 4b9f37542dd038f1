#include "speculum/limits.hpp"

#include "speculum/core.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>

namespace speculum::limits {

void checkJsonDepth(const std::string& text, const std::string& file) {
    int depth = 0;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i;  // skips the escaped character, including \"
            else if (c == '"')
                inString = false;
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                throw inputError(file, "JSON nests deeper than " + std::to_string(kMaxJsonDepth) + " levels (at byte " +
                                           std::to_string(i) + ")");
        } else if (c == ']' || c == '}') {
            if (depth > 0) --depth;  // unbalanced brackets are the JSON parser's to report
        }
    }
}

std::string readJsonText(const std::filesystem::path& path, const std::string& what) {
    const std::string file = path.string();
    if (file.empty()) throw inputError("\"\"", "an empty name is not a " + what);
    std::error_code ec;
    auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) throw inputError(file, "no such " + what);
    if (std::filesystem::is_directory(status)) throw inputError(file, "is a folder, not a " + what);
    if (!std::filesystem::is_regular_file(status))
        throw inputError(file, "is not a regular file (a " + what + " must be one)");
    uint64_t size = std::filesystem::file_size(path, ec);
    if (ec) throw inputError(file, "cannot read the " + what + ": " + ec.message());
    if (size > kMaxTextFileBytes)
        throw inputError(file, "the " + what + " has " + bytesText(size) + ", more than the " +
                                   bytesText(kMaxTextFileBytes) + " limit");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw inputError(file, "cannot open the " + what);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw inputError(file, "cannot read the " + what);
    checkJsonDepth(text, file);
    return text;
}

std::string bytesText(uint64_t bytes) {
    char buf[64];
    if (bytes >= (uint64_t(1) << 30))
        std::snprintf(buf, sizeof buf, "%.2f GiB", double(bytes) / double(uint64_t(1) << 30));
    else
        std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / double(1 << 20));
    return buf;
}

}  // namespace speculum::limits
