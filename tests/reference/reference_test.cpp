// speculum-reference against analytic answers, on scenes built in memory: a mirror plane
// reflecting a box, a mirror sphere under a sky whose radiance encodes direction, and the
// glossy estimator's error falling as 1 / sqrt(spp). Vertices carry no tangents so that the
// shading normal is the interpolated normal (no flat normal-map texel), as the analytic
// answers assume.
#include "reference.hpp"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>

namespace fs = std::filesystem;
using namespace speculum;

namespace {

Vertex vertex(glm::vec3 p, glm::vec3 n) {
    return {p, n, glm::vec4(0.0f), glm::vec2(0.0f)};
}

void addQuad(Primitive& prim, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    uint32_t base = uint32_t(prim.vertices.size());
    for (glm::vec3 p : {a, b, c, d}) prim.vertices.push_back(vertex(p, n));
    prim.indices.insert(prim.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

Mesh box(glm::vec3 lo, glm::vec3 hi, int material) {
    Primitive p;
    p.material = material;
    glm::vec3 c[8];
    for (int i = 0; i < 8; ++i) c[i] = {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
    addQuad(p, c[0], c[4], c[6], c[2]);  // -x
    addQuad(p, c[1], c[3], c[7], c[5]);  // +x
    addQuad(p, c[0], c[1], c[5], c[4]);  // -y
    addQuad(p, c[2], c[6], c[7], c[3]);  // +y
    addQuad(p, c[0], c[2], c[3], c[1]);  // -z
    addQuad(p, c[4], c[5], c[7], c[6]);  // +z
    return {"box", {p}};
}

Mesh floorPlane(float half, int material) {
    Primitive p;
    p.material = material;
    addQuad(p, {-half, 0, -half}, {-half, 0, half}, {half, 0, half}, {half, 0, -half});
    return {"floor", {p}};
}

Mesh sphere(float radius, int slices, int stacks, int material) {
    Primitive p;
    p.material = material;
    for (int j = 0; j <= stacks; ++j)
        for (int i = 0; i <= slices; ++i) {
            float theta = float(M_PI) * float(j) / float(stacks), phi = 2.0f * float(M_PI) * float(i) / float(slices);
            glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
            p.vertices.push_back(vertex(n * radius, n));
        }
    for (int j = 0; j < stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            uint32_t a = uint32_t(j * (slices + 1) + i), b = a + uint32_t(slices + 1);
            p.indices.insert(p.indices.end(), {a, b, b + 1, a, b + 1, a + 1});
        }
    return {"sphere", {p}};
}

Material mirror(float roughness = 0.0f) {
    Material m;
    m.name = "mirror";
    m.baseColor = glm::vec4(1.0f);
    m.metallic = 1.0f;
    m.roughness = roughness;
    m.reflections = MaterialReflections{};
    return m;
}

Material unlit(glm::vec3 color) {
    Material m;
    m.name = "unlit";
    m.baseColor = glm::vec4(color, 1.0f);
    m.unlit = true;
    return m;
}

void finish(Scene& s) {
    s.boundsMin = glm::vec3(1e30f);
    s.boundsMax = glm::vec3(-1e30f);
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        s.instances.push_back({-1, int(i), glm::mat4(1.0f)});
        for (const Primitive& p : s.meshes[i].primitives)
            for (const Vertex& v : p.vertices) {
                s.boundsMin = glm::min(s.boundsMin, v.position);
                s.boundsMax = glm::max(s.boundsMax, v.position);
            }
    }
}

// A sky whose radiance is 0.5 + 0.5 d: any error in a reflection direction shows in its colour.
fs::path writeDirectionSky(const fs::path& dir) {
    const int w = 512, h = 256;
    std::vector<float> px(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::vec3 d = render::equirectDirection({(x + 0.5f) / w, (y + 0.5f) / h});
            for (int c = 0; c < 3; ++c) px[(size_t(y) * w + x) * 3 + size_t(c)] = 0.5f + 0.5f * d[c];
        }
    fs::create_directories(dir);
    fs::path file = dir / "direction_sky.exr";
    auto out = OIIO::ImageOutput::create(file.string());
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    EXPECT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()) &&
                out->close());
    return file;
}

Scene sceneWithSky(const fs::path& dir) {
    Scene s;
    s.path = dir / "scene.gltf";
    s.document = {{"scenes", {{{"extras", {{"environment", "direction_sky.exr"}}}}}}};
    writeDirectionSky(dir);
    return s;
}

fs::path tempDir(const std::string& name) {
    return fs::path(SPECULUM_TEST_TMP) / "reference" / name;
}

std::optional<float> slab(glm::vec3 o, glm::vec3 d, glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 t0 = (lo - o) / d, t1 = (hi - o) / d;
    glm::vec3 tmin = glm::min(t0, t1), tmax = glm::max(t0, t1);
    float enter = std::max({tmin.x, tmin.y, tmin.z}), leave = std::min({tmax.x, tmax.y, tmax.z});
    if (leave < std::max(enter, 0.0f)) return std::nullopt;
    return std::max(enter, 0.0f);
}

}  // namespace

// The box stands on the mirror: every floor pixel's reflection is either the box's unlit red
// or the constant sky. Only pixels whose corners disagree (anti-aliasing edges) may differ.
TEST(Reference, MirrorPlaneReflectsBoxLikeTheAnalyticMirrorImage) {
    Scene s;
    s.materials = {mirror(), unlit({0.9f, 0.1f, 0.05f})};
    const glm::vec3 lo(-1.0f, 0.0f, -4.0f), hi(1.0f, 1.5f, -2.5f);
    const float kFloor = 20.0f;
    s.meshes = {floorPlane(kFloor, 0), box(lo, hi, 1)};
    finish(s);
    const glm::vec3 sky(0.5f, 0.6f, 0.8f), red(0.9f, 0.1f, 0.05f);
    reference::Renderer r(s, {1, 2, 1, 0, 1.0f, {}});
    render::CameraState cam = render::makeCamera({0.3f, 1.2f, 3.0f}, {0.0f, 0.2f, -3.0f}, {0, 1, 0}, glm::radians(60.0f), 128, 72);
    reference::Frame f = r.render(cam);

    // 0: floor shows sky, 1: floor shows box, 2: the primary ray sees the box or the sky.
    auto classify = [&](float px, float py) {
        glm::vec3 o, d;
        render::primaryRay(cam, px, py, o, d);
        std::optional<float> boxT = slab(o, d, lo, hi);
        float floorT = d.y < 0.0f ? -o.y / d.y : -1.0f;
        if (floorT <= 0.0f || (boxT && *boxT < floorT)) return 2;
        glm::vec3 p = o + d * floorT, rd(d.x, -d.y, d.z);
        if (std::abs(p.x) > kFloor || std::abs(p.z) > kFloor) return 2;
        return slab(p, rd, lo, hi) ? 1 : 0;
    };
    int boxPixels = 0, edges = 0, wrong = 0, checked = 0;
    for (uint32_t y = 0; y < f.height; ++y)
        for (uint32_t x = 0; x < f.width; ++x) {
            int centre = classify(float(x), float(y));
            bool edge = false;
            for (float dy : {-0.5f, 0.5f})
                for (float dx : {-0.5f, 0.5f}) edge |= classify(float(x) + dx, float(y) + dy) != centre;
            size_t i = size_t(y) * f.width + x;
            if (edge) {
                ++edges;
                continue;
            }
            ASSERT_EQ(f.reflective[i], centre == 2 ? 0.0f : 1.0f) << "pixel " << x << "," << y;
            if (centre == 2) continue;
            glm::vec3 expected = centre == 1 ? red : sky;
            ++checked;
            boxPixels += centre;
            if (glm::length(f.reflection[i] - expected) > 1e-4f) ++wrong;
        }
    EXPECT_EQ(wrong, 0) << "of " << checked << " floor pixels";
    EXPECT_GT(boxPixels, 200) << "the box's mirror image must cover a real area";
    EXPECT_LT(edges, int(f.width * f.height) / 10);
}

// Every mirror-sphere pixel must show the sky along reflect(d, n) for the analytic sphere.
TEST(Reference, MirrorSphereReflectsAlongTheAnalyticDirection) {
    Scene s = sceneWithSky(tempDir("sphere"));
    s.materials = {mirror()};
    s.meshes = {sphere(1.0f, 256, 128, 0)};
    finish(s);
    reference::Renderer r(s, {1, 2, 1, 0, 1.0f, {}});
    render::CameraState cam = render::makeCamera({0.5f, 0.8f, 4.0f}, {0, 0, 0}, {0, 1, 0}, glm::radians(35.0f), 96, 96);
    reference::Frame f = r.render(cam);
    double sum = 0.0, worst = 0.0;
    int count = 0;
    for (uint32_t y = 0; y < f.height; ++y)
        for (uint32_t x = 0; x < f.width; ++x) {
            glm::vec3 o, d;
            render::primaryRay(cam, float(x), float(y), o, d);
            float b = glm::dot(o, d), c = glm::dot(o, o) - 1.0f, disc = b * b - c;
            // Away from the silhouette, where the tessellation's outline departs from the sphere.
            if (disc < 0.05f) continue;
            glm::vec3 n = glm::normalize(o + d * (-b - std::sqrt(disc)));
            glm::vec3 expected = 0.5f + 0.5f * glm::reflect(d, n);
            size_t i = size_t(y) * f.width + x;
            ASSERT_EQ(f.reflective[i], 1.0f) << "pixel " << x << "," << y;
            double e = glm::length(f.reflection[i] - expected);
            sum += e;
            worst = std::max(worst, e);
            ++count;
        }
    ASSERT_GT(count, 3000);
    std::printf("mirror sphere: %d pixels, mean colour error %.2e, worst %.2e\n", count, sum / count, worst);
    EXPECT_LT(sum / count, 5e-4) << "mean colour error; 5e-4 is about 0.06 degrees of direction";
    EXPECT_LT(worst, 3e-3);
}

namespace {

// A glossy floor (roughness 0.35) under the test sky, and a camera looking down at it: the
// estimator's convergence cases.
Scene glossyFloor(const std::string& name) {
    Scene s = sceneWithSky(tempDir(name));
    s.materials = {mirror(0.35f)};
    s.meshes = {floorPlane(50.0f, 0)};
    finish(s);
    return s;
}

render::CameraState glossyFloorCamera() {
    return render::makeCamera({0, 2.0f, 0}, {0, 0, -3.0f}, {0, 1, 0}, glm::radians(40.0f), 48, 27);
}

}  // namespace

// Monte Carlo error of the glossy lobe falls at least as fast as 1 / sqrt(spp): the lobe's
// directions are a shifted Hammersley set (stratified), so on this smooth sky it falls faster,
// about as 1 / spp (ratios 3.7 a fourfold step, measured), and no faster than spp^-1.5 (8), which
// would mean the "truth" shares the images' points.
TEST(Reference, GlossyErrorFallsAtLeastAsOneOverSqrtSpp) {
    Scene s = glossyFloor("glossy");
    render::CameraState cam = glossyFloorCamera();
    auto renderSpp = [&](uint32_t spp, uint64_t seed) {
        return reference::Renderer(s, {spp, 1, seed, 0, 1.0f, {}}).render(cam).reflection;
    };
    std::vector<glm::vec3> truth = renderSpp(4096, 99);
    std::vector<double> rmse;
    for (uint32_t spp : {4u, 16u, 64u}) {
        std::vector<glm::vec3> img = renderSpp(spp, 7);
        double se = 0.0;
        for (size_t i = 0; i < img.size(); ++i) {
            glm::vec3 d = img[i] - truth[i];
            se += glm::dot(d, d);
        }
        rmse.push_back(std::sqrt(se / double(img.size() * 3)));
    }
    std::printf("glossy rmse at 4/16/64 spp: %.4f %.4f %.4f\n", rmse[0], rmse[1], rmse[2]);
    for (size_t i = 0; i + 1 < rmse.size(); ++i) {
        double ratio = rmse[i] / rmse[i + 1];
        EXPECT_GT(ratio, 1.8) << "rmse " << rmse[i] << " -> " << rmse[i + 1];
        EXPECT_LT(ratio, 8.0) << "rmse " << rmse[i] << " -> " << rmse[i + 1];
    }
    EXPECT_GT(rmse[0], 1e-3) << "the case must be noisy at 4 spp to say anything";
}

// Adaptive sampling's standard error says how far an image is from another seed's: on the pixels
// it calls converged, the RMS difference of two seeds is about sqrt(2) times the RMS of their
// reported errors (0.5x-2x allowed: the error is estimated from a few batches). A stderror that
// ignored the batches' spread, or batches that shared their points, would fail.
TEST(Reference, AdaptiveSamplingReportsItsOwnError) {
    Scene s = glossyFloor("adaptive");
    render::CameraState cam = glossyFloorCamera();
    auto renderSeed = [&](uint64_t seed) {
        reference::Options o;
        o.spp = 8;
        o.bounces = 1;
        o.seed = seed;
        o.targetError = 0.004f;
        o.minBatches = 4;
        o.maxSpp = 2048;
        return reference::Renderer(s, o).render(cam);
    };
    reference::Frame a = renderSeed(3), b = renderSeed(4);
    double diff = 0.0, predicted = 0.0, samples = 0.0;
    int n = 0;
    for (size_t i = 0; i < a.reflection.size(); ++i) {
        if (a.reflective[i] < 0.5f) continue;
        ASSERT_GE(a.stderror[i], 0.0f) << "pixel " << i << ": adaptive pixels know their error";
        glm::vec3 d = glm::clamp(a.reflection[i], 0.0f, 1.0f) - glm::clamp(b.reflection[i], 0.0f, 1.0f);
        diff += std::max({d.x * d.x, d.y * d.y, d.z * d.z});
        predicted += double(a.stderror[i]) * a.stderror[i] + double(b.stderror[i]) * b.stderror[i];
        samples += a.samples[i];
        ++n;
    }
    ASSERT_GT(n, 500);
    double ratio = std::sqrt(diff / predicted);
    std::printf("adaptive: %d pixels, %.0f samples a pixel, seeds differ %.4f RMS, predicted %.4f (ratio %.2f)\n", n,
                samples / n, std::sqrt(diff / n), std::sqrt(predicted / n), ratio);
    EXPECT_GT(ratio, 0.5);
    EXPECT_LT(ratio, 2.0);
    EXPECT_GT(samples / n, 32.0) << "the target must ask for more than the minimum of batches";
}

TEST(Reference, SameSeedSameImageWhateverTheThreadCount) {
    Scene s;
    s.materials = {mirror(0.4f), unlit({1.0f, 0.2f, 0.1f})};
    s.meshes = {floorPlane(20.0f, 0), box({-0.5f, 0.0f, -3.0f}, {0.5f, 1.0f, -2.0f}, 1)};
    finish(s);
    render::CameraState cam = render::makeCamera({0, 1, 2}, {0, 0, -2}, {0, 1, 0}, glm::radians(50.0f), 32, 18);
    auto a = reference::Renderer(s, {8, 1, 5, 1, 1.0f, {}}).render(cam).reflection;
    auto b = reference::Renderer(s, {8, 1, 5, 2, 1.0f, {}}).render(cam).reflection;
    auto c = reference::Renderer(s, {8, 1, 6, 2, 1.0f, {}}).render(cam).reflection;
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
}
