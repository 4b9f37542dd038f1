// The file side of saveScene: one merged buffer (a .glb can hold only one BIN chunk, and one
// .bin beside a .gltf is the simplest self-contained layout), external images copied along,
// and temp-file-then-rename writes.
#include "gltf_document.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>

namespace speculum::gltf {

namespace {

[[noreturn]] void fileError(const std::filesystem::path& path, const std::string& problem) {
    throw Error(ExitCode::Failure, path.string() + ": cannot save: " + problem);
}

std::filesystem::path binPathFor(const std::filesystem::path& path) {
    return path.parent_path() / (path.stem().string() + ".bin");
}

// URIs are percent-encoded (RFC 3986); names with spaces must still load elsewhere.
std::string encodeUri(const std::string& s) {
    static const char* const kHex = "0123456789ABCDEF";
    std::string out;
    for (unsigned char c : s) {
        if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == '/') {
            out += char(c);
        } else {
            out += '%';
            out += kHex[c >> 4];
            out += kHex[c & 15];
        }
    }
    return out;
}

void writeAtomically(const std::filesystem::path& path, const void* data, size_t size) {
    std::filesystem::path tmp = path;
    tmp += ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) fileError(path, "cannot create " + tmp.string());
        out.write(static_cast<const char*>(data), std::streamsize(size));
        out.flush();
        if (!out) {
            out.close();
            std::filesystem::remove(tmp);
            fileError(path, "write to " + tmp.string() + " failed");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        fileError(path, "rename from " + tmp.string() + " failed");
    }
}

bool sameContent(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec) || std::filesystem::file_size(path, ec) != bytes.size() || ec)
        return false;
    std::ifstream in(path, std::ios::binary);
    std::vector<char> chunk(1 << 20);
    for (size_t at = 0; at < bytes.size();) {
        size_t n = std::min(chunk.size(), bytes.size() - at);
        if (!in.read(chunk.data(), std::streamsize(n)) || std::memcmp(chunk.data(), bytes.data() + at, n) != 0)
            return false;
        at += n;
    }
    return true;
}

bool escapesDirectory(const std::filesystem::path& rel) {
    if (!rel.is_relative()) return true;
    for (const auto& part : rel)
        if (part == "..") return true;
    return false;
}

void appendU32(std::vector<uint8_t>& out, uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

}  // namespace

std::vector<uint8_t> mergeBuffers(json& doc, const Scene& scene,
                                  const std::filesystem::path& path) {
    size_t count = doc.contains("buffers") && doc["buffers"].is_array() ? doc["buffers"].size()
                                                                       : 0;
    if (count != scene.buffers.size())
        fileError(path, "the scene's buffers do not match its document");
    if (count == 0) return {};
    std::vector<uint8_t> bin;
    std::vector<uint64_t> base(count);
    for (size_t i = 0; i < count; ++i) {
        bin.resize((bin.size() + 15) & ~size_t(15), 0);  // keeps every view's alignment
        base[i] = bin.size();
        bin.insert(bin.end(), scene.buffers[i].begin(), scene.buffers[i].end());
    }
    if (doc.contains("bufferViews") && doc["bufferViews"].is_array()) {
        for (json& view : doc["bufferViews"]) {
            size_t b = view.value("buffer", size_t(0));
            uint64_t offset = view.value("byteOffset", uint64_t(0));
            view["buffer"] = 0;
            view["byteOffset"] = base.at(b) + offset;
        }
    }
    json merged = doc["buffers"][0];
    merged.erase("uri");
    merged["byteLength"] = bin.size();
    if (path.extension() == ".gltf")
        merged["uri"] = encodeUri(binPathFor(path).filename().string());
    doc["buffers"] = json::array({merged});
    return bin;
}

void copyExternalImages(json& doc, const Scene& scene, const std::filesystem::path& path) {
    if (!doc.contains("images") || !doc["images"].is_array()) return;
    const std::filesystem::path srcDir = scene.path.parent_path();
    const std::filesystem::path dstDir = path.parent_path();
    for (json& image : doc["images"]) {
        if (!image.contains("uri") || !image["uri"].is_string()) continue;
        std::string uri = image["uri"].get<std::string>();
        if (isDataUri(uri)) continue;
        std::filesystem::path rel = percentDecode(uri);
        std::filesystem::path src = srcDir / rel;
        std::filesystem::path dstRel = escapesDirectory(rel) ? rel.filename() : rel;
        std::filesystem::path dst = dstDir / dstRel;
        if (dstRel != rel) image["uri"] = encodeUri(dstRel.generic_string());
        std::error_code ec;
        if (!std::filesystem::is_regular_file(src, ec)) continue;  // warned about at load
        if (std::filesystem::exists(dst, ec) && std::filesystem::equivalent(src, dst, ec))
            continue;
        if (!dst.parent_path().empty()) std::filesystem::create_directories(dst.parent_path(), ec);
        std::filesystem::copy_file(src, dst, std::filesystem::copy_options::overwrite_existing,
                                   ec);
        if (ec) fileError(path, "cannot copy image " + src.string() + ": " + ec.message());
    }
}

void writeOutput(const json& doc, const std::vector<uint8_t>& bin,
                 const std::filesystem::path& path) {
    if (path.extension() == ".gltf") {
        // A .gltf and its .bin are two files, and two renames are not one atomic step: killed
        // between them, the old document would sit beside the new buffer. The editor never
        // changes geometry, so the buffer on disk is nearly always byte-for-byte the one to
        // write: then it is left alone and the save is the document's one rename.
        if (!bin.empty() && !sameContent(binPathFor(path), bin)) writeAtomically(binPathFor(path), bin.data(), bin.size());
        std::string text = doc.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
        writeAtomically(path, text.data(), text.size());
        return;
    }
    std::string text = doc.dump(-1, ' ', false, json::error_handler_t::replace);
    text.resize((text.size() + 3) & ~size_t(3), ' ');
    size_t binPadded = (bin.size() + 3) & ~size_t(3);
    uint64_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + binPadded);
    if (total > 0xFFFFFFFFull) fileError(path, "too large for a .glb (over 4 GiB)");
    std::vector<uint8_t> out;
    out.reserve(total);
    out.insert(out.end(), {'g', 'l', 'T', 'F'});
    appendU32(out, 2);
    appendU32(out, uint32_t(total));
    appendU32(out, uint32_t(text.size()));
    appendU32(out, 0x4E4F534Au);  // "JSON"
    out.insert(out.end(), text.begin(), text.end());
    if (!bin.empty()) {
        appendU32(out, uint32_t(binPadded));
        appendU32(out, 0x004E4942u);  // "BIN\0"
        out.insert(out.end(), bin.begin(), bin.end());
        out.resize(total, 0);
    }
    writeAtomically(path, out.data(), out.size());
}

}  // namespace speculum::gltf
