// The sky in CPU form, the engine's BRDF in C++, and the samplers. The formulas mirror
// shaders/common/brdf.glsl and shaders/engine/ibl_*.glsl line for line where the engine defines
// them, so that a hit point here and a pixel there are shaded alike.
#include "internal.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <thread>

namespace speculum::reference {

// ---- sampling ------------------------------------------------------------------------------

Rng::Rng(uint64_t seed, uint64_t stream) : inc_((stream << 1u) | 1u) {
    next();
    state_ += seed;
    next();
}

uint32_t Rng::next() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

float Rng::uniform() {
    return float(next() >> 8) * (1.0f / 16777216.0f);
}

glm::vec2 hammersley(uint32_t i, uint32_t n) {
    uint32_t bits = i;
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return {(float(i) + 0.5f) / float(n), float(bits) * 2.3283064365386963e-10f};
}

glm::mat3 tangentFrame(glm::vec3 n) {
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z);
    float b = n.x * n.y * a;
    glm::vec3 t(1.0f + s * n.x * n.x * a, s * b, -s * n.x);
    glm::vec3 bt(b, s + n.y * n.y * a, -n.y);
    return glm::mat3(t, bt, n);
}

glm::vec3 importanceSampleGGX(glm::vec2 xi, float alpha) {
    float phi = 2.0f * kPi * xi.x;
    float cosTheta = std::sqrt((1.0f - xi.y) / (1.0f + (alpha * alpha - 1.0f) * xi.y));
    float sinTheta = std::sqrt(std::max(1.0f - cosTheta * cosTheta, 0.0f));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

glm::vec3 sampleVisibleNormal(glm::vec3 v, float alpha, glm::vec2 xi) {
    glm::vec3 vh = glm::normalize(glm::vec3(alpha * v.x, alpha * v.y, v.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    glm::vec3 t1 = lensq > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : glm::vec3(1, 0, 0);
    glm::vec3 t2 = glm::cross(vh, t1);
    float r = std::sqrt(xi.x);
    float phi = 2.0f * kPi * xi.y;
    float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * std::sqrt(std::max(1.0f - p1 * p1, 0.0f)) + s * p2;
    glm::vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return glm::normalize(glm::vec3(alpha * nh.x, alpha * nh.y, std::max(0.0f, nh.z)));
}

// ---- BRDF ----------------------------------------------------------------------------------

float D_GGX(float NoH, float alpha) {
    float a2 = alpha * alpha;
    float d = (NoH * a2 - NoH) * NoH + 1.0f;
    return a2 / (kPi * d * d);
}

float V_SmithGGXCorrelated(float NoV, float NoL, float alpha) {
    float a2 = alpha * alpha;
    float gv = NoL * std::sqrt(NoV * NoV * (1.0f - a2) + a2);
    float gl = NoV * std::sqrt(NoL * NoL * (1.0f - a2) + a2);
    return 0.5f / std::max(gv + gl, 1e-7f);
}

float smithG1(float NoV, float alpha) {
    float a2 = alpha * alpha;
    return 2.0f * NoV / (NoV + std::sqrt(a2 + (1.0f - a2) * NoV * NoV));
}

glm::vec3 F_Schlick(glm::vec3 f0, float VoH) {
    float x = 1.0f - VoH;
    float x2 = x * x;
    return f0 + (glm::vec3(1.0f) - f0) * (x2 * x2 * x);
}

glm::vec3 evalBRDFCos(glm::vec3 n, glm::vec3 v, glm::vec3 l, glm::vec3 baseColor, float metallic,
                      float perceptualRoughness) {
    float NoL = glm::dot(n, l);
    if (NoL <= 0.0f) return glm::vec3(0.0f);
    glm::vec3 h = glm::normalize(v + l);
    float NoV = std::max(glm::dot(n, v), 1e-4f);
    float NoH = std::clamp(glm::dot(n, h), 0.0f, 1.0f);
    float VoH = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
    float r = std::clamp(perceptualRoughness, kMinRoughness, 1.0f);
    float alpha = r * r;
    glm::vec3 F = F_Schlick(specularF0(baseColor, metallic), VoH);
    glm::vec3 specular = D_GGX(NoH, alpha) * V_SmithGGXCorrelated(NoV, NoL, alpha) * F;
    glm::vec3 diffuse = diffuseColor(baseColor, metallic) / kPi;
    return (diffuse + specular) * NoL;
}

// ---- the sky ------------------------------------------------------------------------------

namespace {

constexpr int kLevels = 16;      // prefiltered roughness levels 1/16 .. 16/16
constexpr uint32_t kDfgSize = 64;  // as EnvironmentOptions::dfgSize
constexpr uint32_t kDfgSamples = 1024;
// Narrow lobes need few samples: filtered importance sampling reads pre-blurred mips.
constexpr uint32_t kPrefilterSamplesNarrow = 64;
constexpr uint32_t kPrefilterSamplesWide = 128;
const glm::vec3 kDefaultSky{0.5f, 0.6f, 0.8f};  // engine/render/renderer.cpp

// The extras of the scene the engine shows ("scene", else the first), as renderer.cpp reads them.
const nlohmann::json* sceneExtras(const nlohmann::json& doc) {
    if (!doc.is_object() || !doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty())
        return nullptr;
    size_t index = 0;
    if (doc.contains("scene") && doc["scene"].is_number_unsigned()) index = doc["scene"].get<size_t>();
    if (index >= doc["scenes"].size()) return nullptr;
    const nlohmann::json& s = doc["scenes"][index];
    if (!s.is_object() || !s.contains("extras") || !s["extras"].is_object()) return nullptr;
    return &s["extras"];
}

render::EquirectImage downsample(const render::EquirectImage& src) {
    render::EquirectImage dst;
    dst.width = std::max(1u, src.width / 2);
    dst.height = std::max(1u, src.height / 2);
    dst.texels.resize(size_t(dst.width) * dst.height);
    for (uint32_t y = 0; y < dst.height; ++y)
        for (uint32_t x = 0; x < dst.width; ++x) {
            glm::vec3 sum(0.0f);
            for (uint32_t j = 0; j < 2; ++j)
                for (uint32_t i = 0; i < 2; ++i)
                    sum += src.texel(int(std::min(2 * x + i, src.width - 1)), int(std::min(2 * y + j, src.height - 1)));
            dst.texels[size_t(y) * dst.width + x] = sum * 0.25f;
        }
    return dst;
}

template <class F>
void parallelRows(uint32_t rows, unsigned threads, F&& f) {
    std::vector<std::thread> pool;
    unsigned n = std::max(1u, threads);
    for (unsigned t = 0; t < n; ++t)
        pool.emplace_back([&, t] {
            for (uint32_t y = t; y < rows; y += n) f(y);
        });
    for (auto& th : pool) th.join();
}

std::vector<glm::vec2> buildDfg(unsigned threads) {
    std::vector<glm::vec2> table(size_t(kDfgSize) * kDfgSize);
    parallelRows(kDfgSize, threads, [&](uint32_t j) {
        for (uint32_t i = 0; i < kDfgSize; ++i) {
            float NoV = (float(i) + 0.5f) / float(kDfgSize);
            float roughness = (float(j) + 0.5f) / float(kDfgSize);
            float alpha = roughness * roughness;
            glm::vec3 v(std::sqrt(1.0f - NoV * NoV), 0.0f, NoV);
            glm::vec2 sum(0.0f);
            for (uint32_t s = 0; s < kDfgSamples; ++s) {
                glm::vec3 h = importanceSampleGGX(hammersley(s, kDfgSamples), alpha);
                float VoH = glm::dot(v, h);
                glm::vec3 l = 2.0f * VoH * h - v;
                if (l.z <= 0.0f || VoH <= 0.0f) continue;
                float gVis = V_SmithGGXCorrelated(NoV, l.z, alpha) * 4.0f * l.z * VoH / h.z;
                float x = 1.0f - VoH, fc = x * x * x * x * x;
                sum += glm::vec2(1.0f - fc, fc) * gVis;
            }
            table[size_t(j) * kDfgSize + i] = sum / float(kDfgSamples);
        }
    });
    return table;
}

}  // namespace

Sky::Sky(const Scene& scene, unsigned threads) {
    const nlohmann::json* extras = sceneExtras(scene.document);
    if (extras && extras->contains("exposure")) {
        const auto& e = (*extras)["exposure"];
        if (!e.is_number() || !std::isfinite(e.get<double>()) || e.get<double>() <= 0.0)
            throw inputError(scene.path.string(), "scene extras 'exposure' must be a positive number");
        exposure_ = e.get<float>();
    }
    if (extras && extras->contains("environment")) {
        const auto& env = (*extras)["environment"];
        if (!env.is_string()) throw inputError(scene.path.string(), "scene extras 'environment' must be a path string");
        image_ = render::loadEquirect(scene.path.parent_path() / env.get<std::string>());
        sh_ = render::projectIrradianceSH(image_);
    } else {
        image_ = render::EquirectImage{1, 1, {kDefaultSky}};
        // As the engine's constant Environment: evalSH returns the constant exactly.
        sh_[0] = glm::vec4(kDefaultSky / 0.282095f, 0.0f);
    }
    mips_.push_back(image_);
    while (mips_.back().width > 1 || mips_.back().height > 1) mips_.push_back(downsample(mips_.back()));
    dfg_ = buildDfg(threads);
    threads_ = threads;
}

glm::vec3 Sky::radiance(glm::vec3 dir) const {
    return image_.sample(dir);
}

glm::vec3 Sky::irradianceOverPi(glm::vec3 n) const {
    return render::evalSH(sh_, n);
}

namespace {

// EquirectImage::sample with the direction already turned into uv: the prefilter reads two mips
// per sample and the trigonometry is most of a lookup's cost.
glm::vec3 sampleUV(const render::EquirectImage& image, glm::vec2 uv) {
    float px = uv.x * float(image.width) - 0.5f, py = uv.y * float(image.height) - 0.5f;
    float x0 = std::floor(px), y0 = std::floor(py);
    float fx = px - x0, fy = py - y0;
    int w = int(image.width), h = int(image.height);
    auto at = [&](int x, int y) { return image.texel(((x % w) + w) % w, std::clamp(y, 0, h - 1)); };
    int x = int(x0), y = int(y0);
    return glm::mix(glm::mix(at(x, y), at(x + 1, y), fx), glm::mix(at(x, y + 1), at(x + 1, y + 1), fx), fy);
}

}  // namespace

glm::vec3 Sky::sampleLod(glm::vec3 dir, float lod) const {
    float maxLod = float(mips_.size() - 1);
    lod = std::clamp(lod, 0.0f, maxLod);
    int l0 = int(std::floor(lod));
    int l1 = std::min(l0 + 1, int(mips_.size()) - 1);
    float f = lod - float(l0);
    glm::vec2 uv = render::equirectUV(dir);
    glm::vec3 a = sampleUV(mips_[size_t(l0)], uv);
    return f > 0.0f ? glm::mix(a, sampleUV(mips_[size_t(l1)], uv), f) : a;
}

// Each level is the engine's prefilter (ibl_prefilter.comp: GGX importance sampling with N = V,
// NdotL weights, filtered importance sampling from a box pyramid), at a resolution that keeps
// a texel well below the lobe's width (capped at 256 x 128, near the engine cube's texel size: the narrowest lobes are then
// sharper than their texels, which only the nearly-mirror levels notice).
void Sky::buildLevels() const {
    const bool constant = image_.width == 1 && image_.height == 1;
    const float texelSolidAngle = 4.0f * kPi / float(size_t(image_.width) * image_.height);
    levels_.resize(kLevels);
    for (int k = 0; k < kLevels; ++k) {
        float roughness = float(k + 1) / float(kLevels);
        float alpha = roughness * roughness;
        render::EquirectImage& level = levels_[size_t(k)];
        if (constant) {
            level = image_;
            continue;
        }
        uint32_t width = std::bit_ceil(uint32_t(std::clamp(1.5f * 2.0f * kPi / std::max(alpha, 1e-3f), 32.0f, 256.0f)));
        level.width = std::min(width, image_.width);
        const uint32_t count = alpha < 0.07f ? kPrefilterSamplesNarrow : kPrefilterSamplesWide;
        level.height = std::max(1u, level.width / 2);
        level.texels.resize(size_t(level.width) * level.height);
        struct Sample {
            glm::vec3 l;
            float lod;
        };
        std::vector<Sample> samples;
        for (uint32_t i = 0; i < count; ++i) {
            glm::vec3 h = importanceSampleGGX(hammersley(i, count), alpha);
            glm::vec3 l = 2.0f * h.z * h - glm::vec3(0, 0, 1);
            if (l.z <= 0.0f) continue;
            float pdf = D_GGX(h.z, alpha) * 0.25f;
            float sampleSolidAngle = 1.0f / (float(count) * pdf + 1e-6f);
            samples.push_back({l, 0.5f * std::log2(sampleSolidAngle / texelSolidAngle) + 1.0f});
        }
        parallelRows(level.height, threads_, [&](uint32_t y) {
            for (uint32_t x = 0; x < level.width; ++x) {
                glm::vec3 n = render::equirectDirection({(float(x) + 0.5f) / float(level.width),
                                                         (float(y) + 0.5f) / float(level.height)});
                glm::mat3 frame = tangentFrame(n);
                glm::vec3 sum(0.0f);
                float weight = 0.0f;
                for (const Sample& s : samples) {
                    sum += sampleLod(frame * s.l, s.lod) * s.l.z;
                    weight += s.l.z;
                }
                level.texels[size_t(y) * level.width + x] = sum / std::max(weight, 1e-6f);
            }
        });
    }
}

void Sky::prepare() const {
    std::call_once(levelsBuilt_, [this] { buildLevels(); });
}

glm::vec3 Sky::prefiltered(glm::vec3 dir, float roughness) const {
    prepare();
    float r = std::clamp(roughness, 0.0f, 1.0f) * float(kLevels);
    int k = int(std::floor(r));
    float f = r - float(k);
    auto level = [&](int i) { return i == 0 ? radiance(dir) : levels_[size_t(i - 1)].sample(dir); };
    glm::vec3 a = level(k);
    return f > 0.0f && k < kLevels ? glm::mix(a, level(k + 1), f) : a;
}

glm::vec2 Sky::dfg(float NoV, float roughness) const {
    // A linear clamp sampler at texel centres, as the engine's lookup.
    float x = std::clamp(NoV, 0.0f, 1.0f) * float(kDfgSize) - 0.5f;
    float y = std::clamp(roughness, 0.0f, 1.0f) * float(kDfgSize) - 0.5f;
    int last = int(kDfgSize) - 1;
    int x0 = std::clamp(int(std::floor(x)), 0, last), y0 = std::clamp(int(std::floor(y)), 0, last);
    int x1 = std::min(x0 + 1, last), y1 = std::min(y0 + 1, last);
    float fx = std::clamp(x - float(x0), 0.0f, 1.0f), fy = std::clamp(y - float(y0), 0.0f, 1.0f);
    auto at = [&](int i, int j) { return dfg_[size_t(j) * kDfgSize + size_t(i)]; };
    return glm::mix(glm::mix(at(x0, y0), at(x1, y0), fx), glm::mix(at(x0, y1), at(x1, y1), fx), fy);
}

}  // namespace speculum::reference
