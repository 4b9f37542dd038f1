// Buffers and images. tinygltf does the container work (GLB chunks, data: URIs, buffer-view
// images); we check everything it hands back, load external images ourselves so that a missing
// texture is a warning and a placeholder instead of a failed load, and decode with stb_image.
#include "gltf_document.hpp"

// stb functions static: another layer may link its own copy of stb_image.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <fstream>
#include <map>

namespace speculum::gltf {

namespace {

struct DecodeFailures {
    std::map<int, std::string> reasons;
};

bool decodeRgba8(const unsigned char* bytes, int size, Image& out, std::string& why) {
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(bytes, size, &w, &h, &comp)) {
        why = std::string("cannot decode (") + stbi_failure_reason() + ")";
        return false;
    }
    if (w <= 0 || h <= 0 || uint64_t(w) * uint64_t(h) > kMaxImagePixels) {
        why = "header claims " + std::to_string(w) + "x" + std::to_string(h) + " pixels, more than the " +
              std::to_string(kMaxImagePixels) + " (8192x8192) a texture may have";
        return false;
    }
    stbi_uc* pixels = stbi_load_from_memory(bytes, size, &w, &h, &comp, 4);
    if (!pixels) {
        why = std::string("cannot decode (") + stbi_failure_reason() + ")";
        return false;
    }
    out.width = uint32_t(w);
    out.height = uint32_t(h);
    out.rgba8.assign(pixels, pixels + size_t(w) * size_t(h) * 4);
    stbi_image_free(pixels);
    return true;
}

// tinygltf's image callback. It never fails the load: a bad image becomes a placeholder.
bool decodeForTinygltf(tinygltf::Image* image, const int index, std::string*, std::string*, int,
                       int, const unsigned char* bytes, int size, void* user) {
    Image decoded;
    std::string why;
    if (decodeRgba8(bytes, size, decoded, why)) {
        image->width = int(decoded.width);
        image->height = int(decoded.height);
        image->component = 4;
        image->bits = 8;
        image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
        image->image = std::move(decoded.rgba8);
    } else {
        static_cast<DecodeFailures*>(user)->reasons[index] = why;
    }
    return true;
}

bool readFile(const std::filesystem::path& p, std::vector<uint8_t>& out) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec)) return false;
    std::ifstream in(p, std::ios::binary);
    if (!in) return false;
    out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return !in.bad();
}

// Decoded size of a base64 data: URI (0 when it is not base64), without decoding it.
uint64_t dataUriSize(const std::string& uri) {
    size_t comma = uri.find(',');
    if (comma == std::string::npos || uri.rfind(";base64", comma) == std::string::npos) return 0;
    uint64_t chars = uri.size() - comma - 1;
    uint64_t pad = 0;
    for (size_t i = uri.size(); i > comma + 1 && uri[i - 1] == '=' && pad < 2; --i) ++pad;
    uint64_t rem = chars % 4;  // unpadded base64 ends in 2 or 3 characters
    return chars / 4 * 3 + (rem == 2 ? 1 : rem == 3 ? 2 : 0) - (rem == 0 ? pad : 0);
}

// Our own message for the common case of a missing or short .bin, before tinygltf's.
void checkExternalBuffers(const std::filesystem::path& dir, const Container& c,
                          const Document& d, const Reader& r) {
    for (size_t i = 0; i < d.buffers.size(); ++i) {
        const BufferInfo& b = d.buffers[i];
        std::string where = "buffers[" + std::to_string(i) + "]";
        if (b.uri.empty()) {
            if (i != 0 || !c.glb || !c.hasBin)
                r.fail(where, "has no uri and there is no GLB BIN chunk for it");
            if (c.binLength < b.byteLength)
                r.fail(where, "the GLB BIN chunk has " + std::to_string(c.binLength) +
                                  " bytes, byteLength says " + std::to_string(b.byteLength));
            continue;
        }
        if (isDataUri(b.uri)) {
            uint64_t size = dataUriSize(b.uri);
            if (size < b.byteLength)
                r.fail(where, "data: URI holds " + std::to_string(size) +
                                  " bytes, byteLength says " + std::to_string(b.byteLength));
            continue;
        }
        std::filesystem::path file = dir / percentDecode(b.uri);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            r.fail(where, "buffer file '" + b.uri + "' is missing");
        uint64_t size = std::filesystem::file_size(file, ec);
        if (ec) r.fail(where, "cannot read buffer file '" + b.uri + "'");
        if (size < b.byteLength)
            r.fail(where, "buffer file '" + b.uri + "' has " + std::to_string(size) +
                              " bytes, byteLength says " + std::to_string(b.byteLength));
    }
}

tinygltf::Model runTinygltf(const std::filesystem::path& dir, const Container& c,
                            DecodeFailures& failures, const Reader& r) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&decodeForTinygltf, &failures);
    tinygltf::Model model;
    std::string err, warn, base = dir.empty() ? std::string(".") : dir.string();
    bool ok = false;
    try {
        ok = c.glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, c.bytes.data(),
                                                 unsigned(c.bytes.size()), base)
                   : loader.LoadASCIIFromString(&model, &err, &warn, c.jsonText.data(),
                                                unsigned(c.jsonText.size()), base);
    } catch (const std::exception& e) {
        err += e.what();
    }
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        r.fail("", "glTF parser: " + (err.empty() ? std::string("unknown error") : err));
    }
    return model;
}

void placeholder(Image& img, const std::string& file, const std::string& what,
                 const std::string& why) {
    logWarning(file + ": image " + what + " " + why + "; using a 1x1 white placeholder");
    img.width = img.height = 1;
    img.rgba8 = {255, 255, 255, 255};
    img.placeholder = true;
}

}  // namespace

bool isDataUri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

std::string percentDecode(const std::string& uri) {
    auto hex = [](char ch) -> int {
        if (ch >= '0' && ch <= '9') return ch - '0';
        if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
        if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
        return -1;
    };
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 &&
            hex(uri[i + 2]) >= 0) {
            out += char(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

void loadResources(Scene& scene, const std::filesystem::path& path, const Container& c,
                   const Document& d, const Reader& r) {
    const std::filesystem::path dir = path.parent_path();
    checkExternalBuffers(dir, c, d, r);
    DecodeFailures failures;
    tinygltf::Model model = runTinygltf(dir, c, failures, r);
    if (model.buffers.size() != d.buffers.size() || model.images.size() != d.images.size())
        r.fail("", "glTF parser disagrees about the number of buffers or images");
    for (size_t i = 0; i < d.buffers.size(); ++i) {
        std::vector<uint8_t>& data = model.buffers[i].data;
        if (data.size() < d.buffers[i].byteLength)
            r.fail("buffers[" + std::to_string(i) + "]",
                   "has " + std::to_string(data.size()) + " bytes, byteLength says " +
                       std::to_string(d.buffers[i].byteLength));
        data.resize(d.buffers[i].byteLength);
        scene.buffers.push_back(std::move(data));
    }
    for (size_t i = 0; i < d.images.size(); ++i) {
        const ImageInfo& info = d.images[i];
        Image img;
        img.name = info.name;
        std::string what = "'" + info.name + "'";
        std::string why;
        if (!info.uri.empty() && !isDataUri(info.uri)) {
            what = "'" + info.uri + "'";
            std::vector<uint8_t> bytes;
            if (!readFile(dir / percentDecode(info.uri), bytes) || bytes.empty())
                why = "is missing or unreadable";
            else if (!decodeRgba8(bytes.data(), int(bytes.size()), img, why))
                why = "is unusable: " + why;
        } else if (!model.images[i].image.empty()) {
            img.width = uint32_t(model.images[i].width);
            img.height = uint32_t(model.images[i].height);
            img.rgba8 = std::move(model.images[i].image);
        } else {
            auto it = failures.reasons.find(int(i));
            why = "is unusable: " + (it != failures.reasons.end() ? it->second : "no data");
        }
        if (!why.empty()) placeholder(img, r.file(), what, why);
        scene.images.push_back(std::move(img));
    }
}

}  // namespace speculum::gltf
