// Shading a hit point as the engine shades a pixel (gbuffer_frag.glsl for the surface,
// lighting.frag for the light), with traced reflections where the engine has its reflections
// module. The estimator is written down in README.md.
#include "internal.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

namespace speculum::reference {
namespace {

constexpr uint32_t kMaxLights = 16;  // engine/render/lighting.cpp

struct PreparedLight {
    LightType type = LightType::Point;
    glm::vec3 position{0.0f}, direction{0.0f, 0.0f, -1.0f};
    glm::vec3 radiance{0.0f};
    float range = 0.0f;
    float coneScale = 1.0f, coneOffset = 0.0f;
    bool shadowed = false;
};

// The engine's light list (lighting.cpp buildStaticLighting): the first 16 lights, directional
// ones first, and only the first directional light of the file casts shadows (the shadow map).
std::vector<PreparedLight> prepareLights(const Scene& scene) {
    std::vector<PreparedLight> lights;
    bool shadowAssigned = false;
    bool shadowEnabled = !scene.instances.empty();
    for (const Light& l : scene.lights) {
        if (lights.size() == kMaxLights) break;
        PreparedLight p;
        p.type = l.type;
        p.position = l.position;
        p.direction = glm::length(l.direction) > 0.0f ? glm::normalize(l.direction) : glm::vec3(0, 0, -1);
        p.radiance = l.color * l.intensity;
        p.range = l.range;
        float cosOuter = std::cos(l.outerConeAngle), cosInner = std::cos(l.innerConeAngle);
        p.coneScale = 1.0f / std::max(cosInner - cosOuter, 1e-3f);
        p.coneOffset = -cosOuter * p.coneScale;
        p.shadowed = shadowEnabled && !shadowAssigned && l.type == LightType::Directional;
        shadowAssigned |= p.shadowed;
        lights.push_back(p);
    }
    std::stable_partition(lights.begin(), lights.end(),
                          [](const PreparedLight& l) { return l.type == LightType::Directional; });
    return lights;
}

glm::vec3 srgbToLinear(float r, float g, float b) {
    auto f = [](float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); };
    return {f(r), f(g), f(b)};
}

// Bilinear, repeat (the engine's material sampler without mips); sRGB textures are decoded per
// texel before filtering, as a GPU sRGB view does.
glm::vec4 sampleTexture(const Image& image, glm::vec2 uv, bool srgb) {
    int w = int(image.width), h = int(image.height);
    float px = uv.x * float(w) - 0.5f, py = uv.y * float(h) - 0.5f;
    float x0 = std::floor(px), y0 = std::floor(py);
    float fx = px - x0, fy = py - y0;
    auto at = [&](int x, int y) {
        x = ((x % w) + w) % w;
        y = ((y % h) + h) % h;
        const uint8_t* t = &image.rgba8[(size_t(y) * size_t(w) + size_t(x)) * 4];
        glm::vec4 c(t[0], t[1], t[2], t[3]);
        c /= 255.0f;
        if (srgb) c = glm::vec4(srgbToLinear(c.r, c.g, c.b), c.a);
        return c;
    };
    int x = int(x0), y = int(y0);
    return glm::mix(glm::mix(at(x, y), at(x + 1, y), fx), glm::mix(at(x, y + 1), at(x + 1, y + 1), fx), fy);
}

// What the G-buffer holds for a pixel, plus the hit's position and geometric normal.
struct Surface {
    glm::vec3 position{0.0f};
    glm::vec3 geometricNormal{0.0f};  // unit, out of glTF's front face
    glm::vec3 normal{0.0f};           // shading normal, as the G-buffer stores it
    glm::vec3 baseColor{1.0f};
    glm::vec3 emissive{0.0f};
    float metallic = 1.0f, roughness = 1.0f;
    bool unlit = false, reflective = false;
    float reflectionRoughness = 0.0f;  // after roughnessScale / roughnessOverride
};

}  // namespace

struct Renderer::Impl {
    const Scene& scene;
    Options options;
    std::vector<Material> materials;  // the scene's, then glTF's default
    std::vector<PreparedLight> lights;
    Sky sky;
    std::unique_ptr<Tracer> tracer;

    Impl(const Scene& s, const Options& o);
    const Image* usableImage(const TextureRef& t) const;
    glm::vec3 flatNormalTexel(const Material& m) const;
    Surface surface(const Hit& hit, glm::vec3 dir) const;
    glm::vec3 directAndAmbient(const Surface& s, glm::vec3 v, uint64_t& rays) const;
    glm::vec3 specularWeight(const Surface& s, glm::vec3 v, float roughness) const;
    // `point`: the stratified 2D point a one-sample lobe below uses (reflection()), or null.
    glm::vec3 shade(const Surface& s, glm::vec3 v, uint32_t bounces, uint32_t samples, Rng& rng,
                    uint64_t& rays, const glm::vec2* point = nullptr) const;
    glm::vec3 radiance(glm::vec3 origin, glm::vec3 dir, uint32_t bounces, uint32_t samples, Rng& rng,
                       uint64_t& rays, const glm::vec2* point = nullptr) const;
    glm::vec3 reflection(const Surface& s, glm::vec3 v, uint32_t bounces, uint32_t samples, Rng& rng,
                         uint64_t& rays, const glm::vec2* point = nullptr) const;
    // render.exposure times the scene's extras.exposure: what the tonemap and the metrics multiply by.
    float displayExposure() const { return options.exposure * sky.sceneExposure(); }
    glm::vec3 adaptiveReflection(const Surface& s, glm::vec3 v, Rng& rng, uint64_t& rays, float& samples,
                                 float& stderror) const;
    void renderPixel(const render::CameraState& camera, uint32_t x, uint32_t y, Frame& f, uint64_t& rays) const;
};

Renderer::Impl::Impl(const Scene& s, const Options& o)
    : scene(s), options(o), lights(prepareLights(s)),
      sky(s, o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency())) {
    materials = scene.materials;
    materials.push_back(Material{});
    std::vector<bool> doubleSided;
    for (const Material& m : materials) doubleSided.push_back(m.doubleSided);
    tracer = std::make_unique<Tracer>(scene, doubleSided);
    // Any lit surface without traced reflections takes the split-sum sky.
    bool splitSum = std::any_of(materials.begin(), materials.end(), [](const Material& m) {
        return !m.unlit && !reflects(m);
    });
    if (splitSum) sky.prepare();
}

const Image* Renderer::Impl::usableImage(const TextureRef& t) const {
    if (t.image < 0 || size_t(t.image) >= scene.images.size()) return nullptr;
    const Image& img = scene.images[size_t(t.image)];
    if (img.width == 0 || img.height == 0 || img.rgba8.size() != size_t(img.width) * img.height * 4) return nullptr;
    return &img;
}

// What a material without a normal map puts in the tangent-space normal: the untextured G-buffer
// pipeline uses the exact (0.5, 0.5, 1); a textured material samples the engine's 1x1 default
// normal image, whose 8-bit (128, 128, 255) tilts the normal by 0.3 degrees (scene_gpu.cpp
// resolveMaterial decides which pipeline a material gets).
glm::vec3 Renderer::Impl::flatNormalTexel(const Material& m) const {
    bool placeholderNormal = m.normalTexture.image >= 0 && size_t(m.normalTexture.image) < scene.images.size() &&
                             scene.images[size_t(m.normalTexture.image)].placeholder;
    bool untextured = !usableImage(m.baseColorTexture) && !usableImage(m.metallicRoughnessTexture) &&
                      (placeholderNormal || !usableImage(m.normalTexture)) &&
                      (m.emissive == glm::vec3(0.0f) || !usableImage(m.emissiveTexture));
    return untextured ? glm::vec3(0.5f, 0.5f, 1.0f) : glm::vec3(128.0f / 255.0f, 128.0f / 255.0f, 1.0f);
}

// gbuffer_frag.glsl: material factors times textures, and the shading normal.
Surface Renderer::Impl::surface(const Hit& hit, glm::vec3 dir) const {
    const Geometry& g = tracer->geometry(hit.geometry);
    const uint32_t* tri = &g.indices[size_t(hit.primitive) * 3];
    float w0 = 1.0f - hit.u - hit.v;
    auto lerp = [&](const auto& attr) { return attr[tri[0]] * w0 + attr[tri[1]] * hit.u + attr[tri[2]] * hit.v; };
    const Material& m = materials[g.material >= 0 && size_t(g.material) + 1 < materials.size()
                                      ? size_t(g.material)
                                      : materials.size() - 1];
    Surface s;
    glm::vec3 a = g.positions[tri[0]], b = g.positions[tri[1]], c = g.positions[tri[2]];
    s.position = lerp(g.positions);
    s.geometricNormal = glm::normalize(glm::cross(b - a, c - a));
    bool backFacing = m.doubleSided && glm::dot(s.geometricNormal, dir) > 0.0f;
    glm::vec2 uv = lerp(g.uvs);
    glm::vec4 base = m.baseColor;
    if (const Image* img = usableImage(m.baseColorTexture)) base *= sampleTexture(*img, uv, true);
    s.baseColor = glm::vec3(base);
    s.unlit = m.unlit;
    // As the module's pixelMaterial (modules/reflections/shaders/material.glsl): unlit never reflects.
    s.reflective = reflects(m);
    glm::vec3 n = glm::normalize(lerp(g.normals));
    if (m.unlit) {
        s.normal = backFacing ? -n : n;
        return s;
    }
    glm::vec4 mr(1.0f);
    if (const Image* img = usableImage(m.metallicRoughnessTexture)) mr = sampleTexture(*img, uv, false);
    s.metallic = std::clamp(m.metallic * mr.b, 0.0f, 1.0f);
    s.roughness = std::clamp(m.roughness * mr.g, 0.0f, 1.0f);
    if (s.reflective) {
        const MaterialReflections r = reflectionsOf(m);
        s.reflectionRoughness = r.roughnessOverride ? std::clamp(*r.roughnessOverride, 0.0f, 1.0f)
                                                    : std::clamp(s.roughness * r.roughnessScale, 0.0f, 1.0f);
    }
    if (m.emissive != glm::vec3(0.0f)) {
        glm::vec3 e = m.emissive * m.emissiveStrength;
        if (const Image* img = usableImage(m.emissiveTexture)) e *= glm::vec3(sampleTexture(*img, uv, true));
        s.emissive = e;
    }
    glm::vec4 tangent = lerp(g.tangents);
    glm::vec3 t = glm::vec3(tangent) - n * glm::dot(n, glm::vec3(tangent));
    float tl = glm::dot(t, t);
    if (backFacing) n = -n;
    if (tl > 1e-12f) {
        t /= std::sqrt(tl);
        glm::vec3 bt = glm::cross(n, t) * (tangent.w < 0.0f ? -1.0f : 1.0f);
        glm::vec3 texel = flatNormalTexel(m);
        const Image* nm = usableImage(m.normalTexture);
        if (nm && !nm->placeholder) texel = glm::vec3(sampleTexture(*nm, uv, false));
        glm::vec3 tn = texel * 2.0f - 1.0f;
        tn.x *= m.normalTexture.scale;
        tn.y *= m.normalTexture.scale;
        glm::vec3 mapped = t * tn.x + bt * tn.y + n * tn.z;
        float ml = glm::dot(mapped, mapped);
        if (ml > 1e-12f) n = mapped / std::sqrt(ml);
    }
    s.normal = n;
    return s;
}

// lighting.frag shadeSurface without the specular ambient: punctual lights (the shadowed
// directional light through a shadow ray) and the SH diffuse ambient, plus emission.
glm::vec3 Renderer::Impl::directAndAmbient(const Surface& s, glm::vec3 v, uint64_t& rays) const {
    glm::vec3 color = s.emissive;
    for (const PreparedLight& light : lights) {
        glm::vec3 l, incident;
        if (light.type == LightType::Directional) {
            l = -light.direction;
            incident = light.radiance;
            if (light.shadowed && glm::dot(s.normal, l) > 0.0f &&
                tracer->occluded(offsetOrigin(s.position, s.geometricNormal, l), l, rays))
                continue;
        } else {
            glm::vec3 toLight = light.position - s.position;
            float d2 = std::max(glm::dot(toLight, toLight), 1e-8f);
            l = toLight / std::sqrt(d2);
            float attenuation = 1.0f / d2;
            if (light.range > 0.0f) {
                float ratio2 = d2 / (light.range * light.range);
                float window = std::clamp(1.0f - ratio2 * ratio2, 0.0f, 1.0f);
                attenuation *= window * window;
            }
            if (light.type == LightType::Spot) {
                float cd = glm::dot(light.direction, -l);
                float a = std::clamp(cd * light.coneScale + light.coneOffset, 0.0f, 1.0f);
                attenuation *= a * a;
            }
            incident = light.radiance * attenuation;
        }
        color += evalBRDFCos(s.normal, v, l, s.baseColor, s.metallic, s.roughness) * incident;
    }
    return color + diffuseColor(s.baseColor, s.metallic) * sky.irradianceOverPi(s.normal);
}

// The split-sum scale and bias (F0 * A + B) that multiplies the specular ambient, or the
// reflection on reflective surfaces.
glm::vec3 Renderer::Impl::specularWeight(const Surface& s, glm::vec3 v, float roughness) const {
    float NoV = std::clamp(glm::dot(s.normal, v), 0.0f, 1.0f);
    glm::vec2 ab = sky.dfg(NoV, roughness);
    return specularF0(s.baseColor, s.metallic) * ab.x + ab.y;
}

glm::vec3 Renderer::Impl::shade(const Surface& s, glm::vec3 v, uint32_t bounces, uint32_t samples, Rng& rng,
                                uint64_t& rays, const glm::vec2* point) const {
    if (s.unlit) return s.baseColor;
    glm::vec3 color = directAndAmbient(s, v, rays);
    if (s.reflective && bounces > 0)
        return color + reflection(s, v, bounces - 1, samples, rng, rays, point) *
                           specularWeight(s, v, s.reflectionRoughness);
    glm::vec3 r = glm::reflect(-v, s.normal);
    return color + sky.prefiltered(r, s.roughness) * specularWeight(s, v, s.roughness);
}

glm::vec3 Renderer::Impl::radiance(glm::vec3 origin, glm::vec3 dir, uint32_t bounces, uint32_t samples, Rng& rng,
                                   uint64_t& rays, const glm::vec2* point) const {
    Hit hit = tracer->intersect(origin, dir, rays);
    if (!hit.valid) return sky.radiance(dir);
    return shade(surface(hit, dir), -dir, bounces, samples, rng, rays, point);
}

// The reflection AOV's definition (README.md): the mirror direction's radiance for roughness 0,
// else the GGX BRDF-cosine-weighted mean of incident radiance with F = 1, by visible-normal
// sampling (weight G2 / G1 per sample), self-normalised over `samples` directions. A single
// sample is divided by the lobe's known albedo (DFG A + B) instead, which keeps nested glossy
// bounces unbiased.
glm::vec3 Renderer::Impl::reflection(const Surface& s, glm::vec3 v, uint32_t bounces, uint32_t samples, Rng& rng,
                                     uint64_t& rays, const glm::vec2* point) const {
    if (s.reflectionRoughness <= 0.0f) {
        // One ray serves every sample: the sample budget passes on to whatever it hits.
        glm::vec3 l = glm::reflect(-v, s.normal);
        return radiance(offsetOrigin(s.position, s.geometricNormal, l), l, bounces, samples, rng, rays, point);
    }
    float alpha = s.reflectionRoughness * s.reflectionRoughness;
    glm::mat3 frame = tangentFrame(s.normal);
    glm::vec3 vt = glm::transpose(frame) * v;
    vt.z = std::max(vt.z, 1e-4f);
    vt = glm::normalize(vt);
    // The lobe's directions are a 2D Hammersley set of `samples` points under a random toroidal
    // shift (Cranley-Patterson rotation) drawn from this pixel's stream, and the one-sample lobes
    // their rays meet (a rough wall seen in a glossy floor) take the same set under a second shift
    // and a random permutation (padding, Kollig and Keller 2002). Every point is still uniform,
    // so the estimator is unchanged in expectation and two seeds are two independent estimates;
    // but each 2D projection is stratified. On closed_room.main at 256 samples, two seeds agreed
    // at 25.1 dB with independent points and 30.6 dB in the mirror band with the shift alone
    // (modules/reflections/MEASUREMENTS.md, "converged references").
    auto lobeSample = [&](glm::vec2 xi, glm::vec3& l) -> float {
        glm::vec3 h = sampleVisibleNormal(vt, alpha, xi);
        glm::vec3 lt = 2.0f * glm::dot(vt, h) * h - vt;
        if (lt.z <= 0.0f) return 0.0f;
        l = frame * lt;
        float w = V_SmithGGXCorrelated(vt.z, lt.z, alpha) * 4.0f * lt.z * vt.z / smithG1(vt.z, alpha);
        return w;
    };
    glm::vec3 sum(0.0f);
    float weights = 0.0f;
    if (samples == 1) {
        glm::vec2 xi = point ? *point : glm::vec2(rng.uniform(), rng.uniform());
        glm::vec3 l;
        float w = lobeSample(xi, l);
        if (w > 0.0f) sum = radiance(offsetOrigin(s.position, s.geometricNormal, l), l, bounces, 1, rng, rays) * w;
        glm::vec2 ab = sky.dfg(vt.z, s.reflectionRoughness);
        return sum / std::max(ab.x + ab.y, 1e-4f);
    }
    const glm::vec2 shift(rng.uniform(), rng.uniform()), shiftBelow(rng.uniform(), rng.uniform());
    std::vector<uint32_t> order(samples);
    for (uint32_t i = 0; i < samples; ++i) order[i] = i;
    for (uint32_t i = samples - 1; i > 0; --i) std::swap(order[i], order[rng.next() % (i + 1)]);
    for (uint32_t i = 0; i < samples; ++i) {
        glm::vec3 l;
        float w = lobeSample(glm::fract(hammersley(i, samples) + shift), l);
        if (w <= 0.0f) continue;
        glm::vec2 below = glm::fract(hammersley(order[i], samples) + shiftBelow);
        sum += radiance(offsetOrigin(s.position, s.geometricNormal, l), l, bounces, 1, rng, rays, &below) * w;
        weights += w;
    }
    return weights > 0.0f ? sum / weights : glm::vec3(0.0f);
}

// Batches of options.spp stratified samples until their mean's standard error (display units,
// each channel clamped as the metrics clamp it) is at most options.targetError, at least
// options.minBatches of them, at most options.maxSpp samples. The rooms' error is in few pixels:
// a glossy lobe that meets a point light's highlight on chrome (roughness 0.045, a GGX peak of
// about 1e5) is a firefly at any fixed rate; those pixels take the extra batches, the rest stop at
// the minimum.
glm::vec3 Renderer::Impl::adaptiveReflection(const Surface& s, glm::vec3 v, Rng& rng, uint64_t& rays,
                                             float& samples, float& stderror) const {
    const uint32_t batch = std::max(options.spp, 1u);
    const uint32_t bounces = options.bounces - 1;
    const uint32_t maxSpp = s.reflectionRoughness >= kRoughBand && options.roughMaxSpp ? options.roughMaxSpp
                                                                                       : options.maxSpp;
    glm::vec3 sum = reflection(s, v, bounces, batch, rng, rays);
    samples = float(batch);
    stderror = -1.0f;
    if (options.targetError <= 0.0f || maxSpp < 2 * batch) return sum;
    const float exposure = displayExposure();
    auto display = [&](glm::vec3 x) { return glm::clamp(x * exposure, 0.0f, 1.0f); };
    glm::vec3 first = display(sum), sq = first * first, lin = first;
    auto error = [&](uint32_t k) {
        glm::vec3 mean = lin / float(k);
        glm::vec3 var = glm::max(sq / float(k) - mean * mean, 0.0f) * (float(k) / float(k - 1));
        return std::sqrt(std::max({var.x, var.y, var.z}) / float(k));
    };
    uint32_t k = 1;
    for (; (k + 1) * batch <= maxSpp; ++k) {
        if (k >= std::max(options.minBatches, 2u) && error(k) <= options.targetError) break;
        glm::vec3 b = reflection(s, v, bounces, batch, rng, rays);
        sum += b;
        glm::vec3 d = display(b);
        lin += d;
        sq += d * d;
    }
    samples = float(k * batch);
    stderror = error(k);
    return sum / float(k);
}

void Renderer::Impl::renderPixel(const render::CameraState& camera, uint32_t x, uint32_t y, Frame& f,
                                 uint64_t& rays) const {
    size_t i = size_t(y) * f.width + x;
    glm::vec3 origin, dir;
    render::primaryRay(camera, float(x), float(y), origin, dir);
    Hit hit = tracer->intersect(origin, dir, rays);
    if (!hit.valid) {
        f.linear[i] = sky.radiance(dir);
        return;
    }
    Surface s = surface(hit, dir);
    glm::vec4 clip = camera.viewProj * glm::vec4(s.position, 1.0f);
    f.depth[i] = clip.z / clip.w;
    f.normal[i] = s.normal;
    f.reflective[i] = s.reflective ? 1.0f : 0.0f;
    f.roughness[i] = s.reflective ? s.reflectionRoughness : 0.0f;
    glm::vec3 v = -dir;
    Rng rng(options.seed, uint64_t(y) * f.width + x);
    if (s.reflective) f.reflection[i] = adaptiveReflection(s, v, rng, rays, f.samples[i], f.stderror[i]);
    if (s.unlit) {
        f.linear[i] = s.baseColor;
    } else if (s.reflective) {
        f.linear[i] = directAndAmbient(s, v, rays) + f.reflection[i] * specularWeight(s, v, s.reflectionRoughness);
    } else {
        f.linear[i] = shade(s, v, 0, 1, rng, rays);
    }
}

Renderer::Renderer(const Scene& scene, const Options& options) {
    if (options.bounces < 1) throw argumentError("--bounces must be at least 1");
    impl_ = std::make_unique<Impl>(scene, options);
}

Renderer::~Renderer() = default;

float Renderer::exposure() const {
    return impl_->displayExposure();
}

Frame Renderer::render(const render::CameraState& camera) const {
    auto start = std::chrono::steady_clock::now();
    Frame f;
    f.width = camera.width;
    f.height = camera.height;
    size_t n = size_t(f.width) * f.height;
    f.linear.assign(n, glm::vec3(0.0f));
    f.reflection.assign(n, glm::vec3(0.0f));
    f.normal.assign(n, glm::vec3(0.0f));
    f.depth.assign(n, 0.0f);
    f.reflective.assign(n, 0.0f);
    f.roughness.assign(n, 0.0f);
    f.samples.assign(n, 0.0f);
    f.stderror.assign(n, 0.0f);

    // Rows are handed out one at a time: reflective rows cost far more than sky rows.
    std::atomic<uint32_t> nextRow{0}, rowsDone{0};
    std::atomic<uint64_t> rays{0};
    std::mutex progressMutex;
    unsigned threads = impl_->options.threads ? impl_->options.threads : std::max(1u, std::thread::hardware_concurrency());
    auto work = [&] {
        uint64_t local = 0;
        for (uint32_t y; (y = nextRow.fetch_add(1)) < f.height;) {
            for (uint32_t x = 0; x < f.width; ++x) impl_->renderPixel(camera, x, y, f, local);
            uint32_t done = rowsDone.fetch_add(1) + 1;
            if (impl_->options.progress) {
                std::lock_guard<std::mutex> lock(progressMutex);
                impl_->options.progress(done, f.height);
            }
        }
        rays += local;
    };
    std::vector<std::thread> pool;
    for (unsigned t = 0; t + 1 < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    f.rays = rays.load();
    f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return f;
}

glm::vec3 tonemap(glm::vec3 linear, float exposure) {
    glm::vec3 x = glm::max(linear * exposure, glm::vec3(0.0f));
    glm::vec3 aces = glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
    glm::vec3 out;
    for (int c = 0; c < 3; ++c)
        out[c] = aces[c] <= 0.0031308f ? aces[c] * 12.92f : 1.055f * std::pow(aces[c], 1.0f / 2.4f) - 0.055f;
    return out;
}

}  // namespace speculum::reference
