// Checked JSON access and the .gltf/.glb container: the first line of defence against bad files.
#include "gltf_document.hpp"

#include "speculum/limits.hpp"

#include <cmath>
#include <cstring>
#include <fstream>

namespace speculum::gltf {

namespace {

std::string at(const std::string& where, const char* key) {
    return where.empty() ? std::string(key) : where + "." + key;
}

uint32_t readU32(const uint8_t* p) {
    // GLB is little-endian by definition; assemble bytes so the host's order never matters.
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

}  // namespace

const char* jsonTypeName(const json& v) {
    if (v.is_number_integer()) return "an integer";
    if (v.is_number()) return "a number";
    if (v.is_string()) return "a string";
    if (v.is_boolean()) return "a boolean";
    if (v.is_array()) return "an array";
    if (v.is_object()) return "an object";
    return "null";
}

std::string elementName(const char* array, size_t i, const json& obj) {
    std::string s = std::string(array) + "[" + std::to_string(i) + "]";
    auto it = obj.find("name");
    if (obj.is_object() && it != obj.end() && it->is_string() && !it->get<std::string>().empty())
        s += " \"" + it->get<std::string>() + "\"";
    return s;
}

void Reader::fail(const std::string& where, const std::string& problem) const {
    throw inputError(file_, where.empty() ? problem : where + ": " + problem);
}

const json* Reader::object(const json& obj, const char* key, const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) return nullptr;
    if (!it->is_object())
        fail(at(where, key), std::string("expected an object, got ") + jsonTypeName(*it));
    return &*it;
}

const json* Reader::array(const json& obj, const char* key, const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) return nullptr;
    if (!it->is_array())
        fail(at(where, key), std::string("expected an array, got ") + jsonTypeName(*it));
    return &*it;
}

std::optional<double> Reader::optNumber(const json& obj, const char* key,
                                        const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) return std::nullopt;
    if (!it->is_number())
        fail(at(where, key), std::string("expected a number, got ") + jsonTypeName(*it));
    double v = it->get<double>();
    if (!std::isfinite(v)) fail(at(where, key), "number is not finite");
    return v;
}

double Reader::number(const json& obj, const char* key, const std::string& where,
                      double def) const {
    return optNumber(obj, key, where).value_or(def);
}

int64_t Reader::integer(const json& obj, const char* key, const std::string& where,
                        int64_t def) const {
    auto it = obj.find(key);
    if (it == obj.end()) return def;
    if (it->is_number_integer()) return it->get<int64_t>();
    // Some writers emit 3.0 for 3; accept integral floats but nothing else.
    if (it->is_number_float()) {
        double v = it->get<double>();
        if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.0e15)
            return static_cast<int64_t>(v);
    }
    fail(at(where, key), std::string("expected an integer, got ") + jsonTypeName(*it));
}

int Reader::index(const json& obj, const char* key, const std::string& where, size_t count,
                  const char* what, bool required) const {
    if (!obj.contains(key)) {
        if (required) fail(at(where, key), "missing (required)");
        return -1;
    }
    int64_t v = integer(obj, key, where, -1);
    if (v < 0 || uint64_t(v) >= count)
        fail(at(where, key), "index " + std::to_string(v) + " out of range (the file has " +
                                 std::to_string(count) + " " + what + ")");
    return static_cast<int>(v);
}

std::string Reader::string(const json& obj, const char* key, const std::string& where,
                           const std::string& def) const {
    auto it = obj.find(key);
    if (it == obj.end()) return def;
    if (!it->is_string())
        fail(at(where, key), std::string("expected a string, got ") + jsonTypeName(*it));
    return it->get<std::string>();
}

bool Reader::boolean(const json& obj, const char* key, const std::string& where,
                     bool def) const {
    auto it = obj.find(key);
    if (it == obj.end()) return def;
    if (!it->is_boolean())
        fail(at(where, key), std::string("expected a boolean, got ") + jsonTypeName(*it));
    return it->get<bool>();
}

std::vector<float> Reader::floats(const json& obj, const char* key, const std::string& where,
                                  size_t n, std::vector<float> def) const {
    const json* a = array(obj, key, where);
    if (!a) return def;
    if (a->size() != n)
        fail(at(where, key), "expected " + std::to_string(n) + " numbers, got " +
                                 std::to_string(a->size()));
    std::vector<float> out;
    for (const json& v : *a) {
        if (!v.is_number())
            fail(at(where, key), std::string("expected numbers, found ") + jsonTypeName(v));
        double d = v.get<double>();
        if (!std::isfinite(d) || std::fabs(d) > 3.0e38)
            fail(at(where, key), "number is not finite");
        out.push_back(static_cast<float>(d));
    }
    return out;
}

const json& Reader::topArray(const json& doc, const char* key) const {
    static const json kEmpty = json::array();
    const json* a = array(doc, key, "");
    if (!a) return kEmpty;
    for (size_t i = 0; i < a->size(); ++i)
        if (!(*a)[i].is_object())
            fail(std::string(key) + "[" + std::to_string(i) + "]",
                 std::string("expected an object, got ") + jsonTypeName((*a)[i]));
    return *a;
}

Container readContainer(const std::filesystem::path& path, const Reader& r) {
    Container c;
    std::error_code ec;
    auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) r.fail("", "no such file");
    if (std::filesystem::is_directory(status)) r.fail("", "is a folder, not a glTF file");
    if (!std::filesystem::is_regular_file(status)) r.fail("", "is not a regular file (a glTF scene must be one)");
    // The whole file is read into memory: no more than the largest buffer plus its JSON.
    const uint64_t fileBytes = std::filesystem::file_size(path, ec);
    if (!ec && fileBytes > kMaxBufferBytes + limits::kMaxTextFileBytes)
        r.fail("", "the file has " + limits::bytesText(fileBytes) + ", more than the " +
                       limits::bytesText(kMaxBufferBytes + limits::kMaxTextFileBytes) + " a scene file may have");
    std::ifstream in(path, std::ios::binary);
    if (!in) r.fail("", "cannot open the file");
    c.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) r.fail("", "cannot read the file");
    if (c.bytes.empty()) r.fail("", "the file is empty");

    c.glb = c.bytes.size() >= 4 && std::memcmp(c.bytes.data(), "glTF", 4) == 0;
    if (!c.glb) {
        if (path.extension() == ".glb") r.fail("", "not a GLB file (no 'glTF' magic)");
        c.jsonText.assign(c.bytes.begin(), c.bytes.end());
        return c;
    }
    const uint64_t size = c.bytes.size();
    const uint8_t* p = c.bytes.data();
    if (size < 20) r.fail("", "truncated GLB: " + std::to_string(size) + " bytes, no JSON chunk");
    if (readU32(p + 4) != 2)
        r.fail("", "unsupported GLB version " + std::to_string(readU32(p + 4)) + " (need 2)");
    uint64_t declared = readU32(p + 8);
    if (declared > size)
        r.fail("", "truncated GLB: header says " + std::to_string(declared) + " bytes, file has " +
                       std::to_string(size));
    uint64_t jsonLength = readU32(p + 12);
    if (readU32(p + 16) != 0x4E4F534Au) r.fail("", "GLB: the first chunk is not JSON");
    if (20 + jsonLength > declared)
        r.fail("", "truncated GLB: the JSON chunk runs past the end of the file");
    c.jsonText.assign(reinterpret_cast<const char*>(p + 20), jsonLength);
    uint64_t next = 20 + ((jsonLength + 3) & ~uint64_t(3));
    if (next + 8 <= declared && readU32(p + next + 4) == 0x004E4942u) {
        c.binLength = readU32(p + next);
        c.binOffset = next + 8;
        if (c.binOffset + c.binLength > declared)
            r.fail("", "truncated GLB: the BIN chunk runs past the end of the file");
        c.hasBin = true;
    }
    return c;
}

json parseJson(const std::string& text, const Reader& r) {
    // Before either JSON parser sees it: tinygltf recurses per level and overflowed the stack.
    limits::checkJsonDepth(text, r.file());
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::exception& e) {
        r.fail("", std::string("not valid JSON (") + e.what() + ")");
    }
    if (!doc.is_object())
        r.fail("", std::string("not a glTF document: the top level is ") + jsonTypeName(doc) +
                       ", not an object");
    return doc;
}

}  // namespace speculum::gltf
