// CMOs on lavapipe: the tracers of modules/probes/shaders/cmo.glsl on a CMO captured by the probes
// module in an analytic scene (a 4 m box room with a 0.8 m box in it), against CPU ray casts;
// the hierarchical tracer against the constant-step one at a fine step; and the module's CMO
// path end to end (a CMO changes the reflection where screen space cannot see).
#include "render_test_support.hpp"

#include "speculum/gpu/pipeline.hpp"
#include "speculum/probes/probes.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <memory>
#include <random>

#include "probes/shaders/cmo.h"

using namespace speculum;
using render::test::cubeTexel;
using render::test::Texel;

namespace {

constexpr double kRoom = 2.0;  // x, z in [-2, 2], y in [0, 4]
const glm::dvec3 kBoxMin(0.2, 0.0, -0.8), kBoxMax(1.0, 0.8, 0.0);
const glm::vec3 kCmoCenter(-0.6f, 1.6f, 0.7f);
constexpr uint32_t kRes = 128;

// The room's six inward faces and the box's five outward ones (its bottom lies on the floor);
// `open`: without the room's +z wall, an opening onto the sky.
Scene boxRoom(bool open = false) {
    Scene scene;
    scene.materials = {render::test::greyMaterial("grey", 0.6f, 0.8f)};
    using render::test::square;
    const float r = float(kRoom);
    const Primitive walls[] = {square({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, r, 0), square({0, 2 * r, 0}, {1, 0, 0}, {0, 0, 1}, r, 0),
                               square({-r, r, 0}, {0, 0, -1}, {0, 1, 0}, r, 0), square({r, r, 0}, {0, 0, 1}, {0, 1, 0}, r, 0),
                               square({0, r, -r}, {1, 0, 0}, {0, 1, 0}, r, 0), square({0, r, r}, {-1, 0, 0}, {0, 1, 0}, r, 0)};
    for (size_t i = 0; i < (open ? 5u : 6u); ++i) render::test::addMesh(scene, walls[i]);
    const glm::vec3 c = glm::vec3((kBoxMin + kBoxMax) * 0.5);
    const float h = float((kBoxMax.x - kBoxMin.x) * 0.5);
    for (const auto& p : {square(c + glm::vec3(0, h, 0), {1, 0, 0}, {0, 0, -1}, h, 0),
                          square(c + glm::vec3(h, 0, 0), {0, 0, -1}, {0, 1, 0}, h, 0),
                          square(c - glm::vec3(h, 0, 0), {0, 0, 1}, {0, 1, 0}, h, 0),
                          square(c + glm::vec3(0, 0, h), {1, 0, 0}, {0, 1, 0}, h, 0),
                          square(c - glm::vec3(0, 0, h), {-1, 0, 0}, {0, 1, 0}, h, 0)})
        render::test::addMesh(scene, p);
    Node cmo;
    cmo.name = "cmo";
    cmo.translation = kCmoCenter;
    ReflectionProbe probe;
    probe.kind = ProbeKind::Cmo;
    probe.resolution = kRes;
    cmo.probe = probe;
    cmo.world = glm::translate(glm::mat4(1.0f), kCmoCenter);
    scene.nodes.push_back(cmo);
    scene.roots.push_back(int(scene.nodes.size()) - 1);  // probes follow the active scene
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    sun.intensity = 2.0f;
    scene.lights.push_back(sun);
    return scene;
}

// Entry and exit of the ray through the box [lo, hi] (slabs); entry > exit: no intersection.
glm::dvec2 slabs(glm::dvec3 o, glm::dvec3 r, glm::dvec3 lo, glm::dvec3 hi) {
    double tin = -std::numeric_limits<double>::infinity(), tout = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::abs(r[a]) < 1e-12) {
            if (o[a] < lo[a] || o[a] > hi[a]) return {1.0, 0.0};
            continue;
        }
        double t1 = (lo[a] - o[a]) / r[a], t2 = (hi[a] - o[a]) / r[a];
        tin = std::max(tin, std::min(t1, t2));
        tout = std::min(tout, std::max(t1, t2));
    }
    return {tin, tout};
}

// The first surface along the ray from o (in the room, outside the box).
double castRay(glm::dvec3 o, glm::dvec3 r) {
    glm::dvec2 room = slabs(o, r, {-kRoom, 0, -kRoom}, {kRoom, 2 * kRoom, kRoom});
    glm::dvec2 box = slabs(o, r, kBoxMin, kBoxMax);
    double t = room.y;
    if (box.x <= box.y && box.x > 0.0) t = std::min(t, box.x);
    return t;
}

bool insideBox(glm::dvec3 p, double margin) {
    return glm::all(glm::greaterThan(p, kBoxMin - margin)) && glm::all(glm::lessThan(p, kBoxMax + margin));
}

// Whether the CMO's centre sees point q (the segment between them misses the box, grown by margin).
bool cmoSees(glm::dvec3 q, double margin = 0.0) {
    glm::dvec3 c(kCmoCenter);
    glm::dvec3 d = q - c;
    double len = glm::length(d);
    glm::dvec2 box = slabs(c, d / len, kBoxMin - margin, kBoxMax + margin);
    return !(box.x <= box.y && box.y > 0.0 && box.x < len - 1e-4);
}

// The query of modules/probes/shaders/cmo_trace_test.comp.
struct Query {
    glm::vec4 origin;  // w 1: on a surface
    glm::vec4 dir;     // w ray length
    glm::vec4 normal;
};

struct Ray {
    glm::dvec3 o, r;
    double tTrue;
    bool inView;  // the whole segment up to the hit, and the hit, are seen by the CMO
};

std::vector<Ray> makeRays(size_t count) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-kRoom + 0.1, kRoom - 0.1), uy(0.05, 2 * kRoom - 0.1);
    std::normal_distribution<double> g;
    std::vector<Ray> rays;
    while (rays.size() < count) {
        Ray ray;
        bool onFloor = rays.size() % 2 == 0;
        ray.o = {u(rng), onFloor ? 0.0 : uy(rng), u(rng)};
        if (insideBox(ray.o, 0.02) || !cmoSees(ray.o + glm::dvec3(0, onFloor ? 1e-3 : 0, 0))) continue;
        glm::dvec3 r(g(rng), g(rng), g(rng));
        if (glm::length(r) < 1e-3) continue;
        r = glm::normalize(r);
        if (onFloor) r.y = std::abs(r.y) + 0.05, r = glm::normalize(r);
        ray.r = r;
        ray.tTrue = castRay(ray.o, r);
        ray.inView = true;
        for (int k = 1; k <= 400 && ray.inView; ++k) ray.inView = cmoSees(ray.o + r * (ray.tTrue * (k / 400.0) - 1e-3));
        rays.push_back(ray);
    }
    return rays;
}

// Rays from inside the open room (boxRoom(true)) that leave it through its opening at +z and cross
// a side wall's plane (x = +-2) 2 mm-10 cm past the wall's end, into the sky: a miss for a ray cast.
// The CMO sees each ray's start and, past the opening, each ray's end behind the side wall.
std::vector<Ray> makeOpeningRays(size_t count) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> ux(-kRoom + 0.2, kRoom - 0.2), uy(0.3, 2 * kRoom - 0.3), uz(-kRoom + 0.2, 1.0);
    std::uniform_real_distribution<double> past(0.002, 0.1), side(0.0, 1.0);
    std::vector<Ray> rays;
    while (rays.size() < count) {
        Ray ray;
        ray.o = {ux(rng), uy(rng), uz(rng)};
        if (insideBox(ray.o, 0.02) || !cmoSees(ray.o)) continue;
        double sx = side(rng) < 0.5 ? -1.0 : 1.0;
        glm::dvec3 target(sx * kRoom, uy(rng), kRoom + past(rng));  // on the wall's plane, past its end
        ray.r = glm::normalize(target - ray.o);
        // Through the opening (within the room's section at z = 2), clear of the box, and seen by
        // the CMO all the way there with 2 cm to spare (a ray passing behind the box is another
        // case: the box's unseen side goes on behind its silhouette; one grazing it is within a
        // texel of a hit on it).
        double tOut = (kRoom - ray.o.z) / ray.r.z;
        glm::dvec3 out = ray.o + ray.r * tOut;
        glm::dvec2 box = slabs(ray.o, ray.r, kBoxMin, kBoxMax);
        if (std::abs(out.x) >= kRoom || out.y <= 0.0 || out.y >= 2 * kRoom || (box.x <= box.y && box.x > 0.0)) continue;
        bool seen = true;
        for (int k = 1; k <= 200 && seen; ++k) seen = cmoSees(ray.o + ray.r * (tOut * k / 200.0), 0.02);
        if (!seen) continue;
        ray.tTrue = std::numeric_limits<double>::infinity();
        ray.inView = false;
        rays.push_back(ray);
    }
    return rays;
}

class CmoRig {
public:
    explicit CmoRig(const gpu::Context& ctx)
        : ctx_(ctx),
          pipeline_(gpu::createComputePipeline(ctx, "probes/cmo_trace_test.comp", sizeof(glm::vec4), "test.cmo.trace")),
          sampler_(gpu::createSampler(ctx, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, false)) {}

    // Per ray: (status, tHit, iterations, 0) of the hierarchical tracer, then of the linear one.
    std::vector<glm::vec4> run(const probes::Probes& module, const std::vector<Ray>& rays, float step) {
        const probes::CmoInfo& info = module.cmos().at(0);
        probes::shader::CmoRecord rec{glm::vec4(info.center, float(kRes)),
                                      glm::vec4(0.0f, 0.0f, float(std::bit_width(kRes)), 2.0f / float(kRes))};
        gpu::Buffer recs(ctx_, sizeof(rec), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "test.cmo.records");
        std::memcpy(recs.mapped(), &rec, sizeof(rec));
        std::vector<Query> queries;
        for (size_t i = 0; i < rays.size(); ++i) {
            bool floor = rays[i].o.y == 0.0;
            queries.push_back({glm::vec4(glm::vec3(rays[i].o), floor ? 1.0f : 0.0f), glm::vec4(glm::vec3(rays[i].r), 20.0f),
                               glm::vec4(0, 1, 0, 0)});
        }
        VkImageView distance = module.cmoDistance().view();
        return render::test::runQueries(ctx_, pipeline_, queries, 2, [&](VkCommandBuffer cmd, gpu::DescriptorWriter& w) {
            // The tracers read distances only: the other arrays are bound to the distance array.
            const VkImageLayout general = VK_IMAGE_LAYOUT_GENERAL;
            w.buffer("CmoBuffer", recs.get())
                .sampled("cmoDistance", distance, sampler_.get(), general)
                .sampled("cmoLayers", distance, sampler_.get(), general)
                .sampled("cmoAttr", distance, sampler_.get(), general)
                .sampled("cmoAlbedo", distance, sampler_.get(), general)
                .push(ctx_, cmd, pipeline_);
            glm::vec4 params(step, 0.05f, 100000.0f, float(queries.size()));
            vkCmdPushConstants(cmd, pipeline_.layout(), kCompute, 0, sizeof(params), &params);
        });
    }

private:
    static constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;
    const gpu::Context& ctx_;
    gpu::Pipeline pipeline_;
    gpu::Unique<VkSampler> sampler_;
};

// Whether two hit points lie within one cube texel of each other as the CMO sees them: the same
// face and at most one texel apart, or across a face seam at most 1.5 texel angles apart.
bool withinOneTexel(glm::dvec3 a, glm::dvec3 b) {
    glm::dvec3 c(kCmoCenter);
    Texel ta = cubeTexel(a - c, kRes), tb = cubeTexel(b - c, kRes);
    if (ta.face == tb.face) return std::abs(ta.x - tb.x) <= 1 && std::abs(ta.y - tb.y) <= 1;
    double cosAngle = glm::dot(glm::normalize(a - c), glm::normalize(b - c));
    return std::acos(std::clamp(cosAngle, -1.0, 1.0)) <= 1.5 * 2.0 / kRes;
}

}  // namespace

class CmoGpu : public render::test::SharedContextTest<CmoGpu> {
protected:
    // One baked CMO in the box room, shared by the tests (a bake is six renders).
    struct Baked {
        render::Renderer renderer;
        probes::Probes probes;
        Baked(const gpu::Context& ctx, const Scene& scene) : renderer(ctx, scene), probes(ctx, renderer) {
            probes.update();
        }
    };
    static Baked& baked() {
        static Scene scene = boxRoom();
        if (!baked_) baked_ = std::make_unique<Baked>(*ctx_, scene);
        return *baked_;
    }
    static Baked& bakedOpen() {
        static Scene scene = boxRoom(true);
        if (!bakedOpen_) bakedOpen_ = std::make_unique<Baked>(*ctx_, scene);
        return *bakedOpen_;
    }
    // Before the shared context goes.
    static void TearDownTestSuite() {
        baked_.reset();
        bakedOpen_.reset();
        SharedContextTest<CmoGpu>::TearDownTestSuite();
    }
    static inline std::unique_ptr<Baked> baked_, bakedOpen_;
};

// Of the rays that stay within the CMO's view up to their hit, at least 99% find the hit the CPU
// ray cast predicts, within one cube texel (hierarchical tracer).
TEST_F(CmoGpu, HitsAgreeWithCpuRayCastsWithinOneTexel) {
    Baked& b = baked();
    ASSERT_EQ(b.probes.cmos().size(), 1u);
    std::vector<Ray> rays = makeRays(3000);
    CmoRig rig(*ctx_);
    std::vector<glm::vec4> res = rig.run(b.probes, rays, 0.01f);
    size_t eligible = 0, good = 0, missed = 0, unresolved = 0, wrong = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        if (!rays[i].inView) continue;
        ++eligible;
        const glm::vec4& h = res[2 * i];
        if (int(h.x) != 1) {
            (int(h.x) == 2 ? unresolved : missed)++;
            continue;
        }
        glm::dvec3 gpu = rays[i].o + rays[i].r * double(h.y), cpu = rays[i].o + rays[i].r * rays[i].tTrue;
        withinOneTexel(gpu, cpu) ? ++good : ++wrong;
    }
    std::cout << "[cmo] in view " << eligible << " of " << rays.size() << " rays: " << good << " within one texel, "
              << wrong << " elsewhere, " << missed << " missed, " << unresolved << " unresolved\n";
    ASSERT_GT(eligible, 1000u);
    EXPECT_GE(double(good), 0.99 * double(eligible));
}

// Issue 24, "CMOs that never hurt": a ray that leaves the room through its opening past a side
// wall's end passes behind that wall as the CMO sees it, and the wall's edge texels place its end
// anywhere within half a texel. Neither tracer reports such a ray as a hit (on the wall): it is
// a miss or unresolved, and the chain goes on. Before the opening rule (cmo.glsl, cmoRefine),
// 180 of these 2,000 rays were hits on the wall (hierarchical), 188 (constant step); the rest
// were misses, as now, or passed behind by more than the tolerance.
TEST_F(CmoGpu, RayPastAnOpeningsEdgeIsNeverAHit) {
    Baked& b = bakedOpen();
    ASSERT_EQ(b.probes.cmos().size(), 1u);
    std::vector<Ray> rays = makeOpeningRays(2000);
    CmoRig rig(*ctx_);
    std::vector<glm::vec4> res = rig.run(b.probes, rays, 0.01f);
    size_t hits[2] = {0, 0}, misses[2] = {0, 0};
    for (size_t i = 0; i < rays.size(); ++i)
        for (int k = 0; k < 2; ++k) {
            hits[k] += int(res[2 * i + k].x) == 1;
            misses[k] += int(res[2 * i + k].x) == 0;
        }
    std::cout << "[cmo] rays past the opening's edge: hierarchical " << hits[0] << " hits, " << misses[0]
              << " misses; constant step " << hits[1] << " hits, " << misses[1] << " misses, of " << rays.size() << "\n";
    EXPECT_EQ(hits[0], 0u);
    EXPECT_EQ(hits[1], 0u);
}

// At a fine step (5 mm) the constant-step tracer and the hierarchy agree on 99% of the rays
// (the same outcome, hits within one texel); the iterations of each are reported (the bench's
// "hierarchy vs constant step" figure).
TEST_F(CmoGpu, HierarchicalAgreesWithConstantStepAtAFineStep) {
    Baked& b = baked();
    std::vector<Ray> rays = makeRays(3000);
    CmoRig rig(*ctx_);
    std::vector<glm::vec4> res = rig.run(b.probes, rays, 0.005f);
    size_t agree = 0, both = 0;
    double itH = 0.0, itL = 0.0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const glm::vec4 &h = res[2 * i], &l = res[2 * i + 1];
        itH += h.z;
        itL += l.z;
        if (int(h.x) != int(l.x)) continue;
        if (int(h.x) != 1) {
            ++agree;
            continue;
        }
        ++both;
        agree += withinOneTexel(rays[i].o + rays[i].r * double(h.y), rays[i].o + rays[i].r * double(l.y));
    }
    std::cout << "[cmo] hierarchical vs linear (5 mm): agree on " << agree << " of " << rays.size() << " rays (" << both
              << " hits); mean iterations " << itH / rays.size() << " hierarchical, " << itL / rays.size()
              << " linear (" << itL / std::max(itH, 1.0) << "x)\n";
    EXPECT_GE(double(agree), 0.99 * double(rays.size()));
}

// A time-sliced CMO (one face per update) is left out of tracing until its sixth face, then
// equals the once-baked CMO: the same distances (every level) and radiance, bit for bit.
TEST_F(CmoGpu, TimeSlicedEqualsOnceBakedAfterSixUpdates) {
    Scene once = boxRoom();
    Scene sliced = once;
    sliced.nodes.back().probe->update = ProbeUpdate::TimeSliced;
    render::Renderer ra(*ctx_, once), rb(*ctx_, sliced);
    probes::Probes a(*ctx_, ra), b(*ctx_, rb);
    a.update();
    auto traced = [](probes::Probes& p) {
        FrameGraph fg(FrameGraphConfig{8, 8});
        return p.addPasses(fg).cmos.count;
    };
    for (int frame = 0; frame < 6; ++frame) {
        EXPECT_EQ(traced(b), 0u) << "after " << frame << " updates";
        b.update();
    }
    EXPECT_EQ(traced(b), 1u);
    EXPECT_EQ(traced(a), 1u);
    for (const gpu::Image* pair : {&a.cmoDistance(), &a.cmoRadiance()}) {
        const gpu::Image& other = pair == &a.cmoDistance() ? b.cmoDistance() : b.cmoRadiance();
        for (uint32_t mip : {0u, pair->desc().mips - 1})
            for (uint32_t layer = 0; layer < 6; ++layer)
                EXPECT_EQ(gpu::readImageRGBA(*ctx_, pair->get(), pair->desc(), VK_IMAGE_LAYOUT_GENERAL, mip, layer),
                          gpu::readImageRGBA(*ctx_, other.get(), other.desc(), VK_IMAGE_LAYOUT_GENERAL, mip, layer))
                    << "mip " << mip << " face " << layer;
    }
}

// The editor's live re-bake: a CMO moved with moveProbe is left out of tracing while its faces
// are captured again, one per update, and after six updates holds exactly the distances (every
// level) of a CMO baked at the new place from the start.
TEST_F(CmoGpu, MovedCmoIsCapturedAgainFromItsNewPlace) {
    const glm::vec3 target = kCmoCenter + glm::vec3(0.5f, -0.3f, -0.4f);
    const glm::mat4 world = glm::translate(glm::mat4(1.0f), target);
    Scene there = boxRoom();
    there.nodes.back().translation = target;
    there.nodes.back().world = world;
    Scene here = boxRoom();
    render::Renderer ra(*ctx_, here), rb(*ctx_, there);
    probes::Probes moved(*ctx_, ra), fresh(*ctx_, rb);
    moved.update();
    fresh.update();
    auto traced = [](probes::Probes& p) {
        FrameGraph fg(FrameGraphConfig{8, 8});
        return p.addPasses(fg).cmos.count;
    };
    ASSERT_TRUE(moved.moveProbe(int(here.nodes.size() - 1), world));
    EXPECT_FALSE(moved.moveProbe(7, world)) << "node 7 does not exist";
    for (int frame = 0; frame < 6; ++frame) {
        EXPECT_TRUE(moved.relocating());
        EXPECT_EQ(traced(moved), 0u) << "after " << frame << " updates";
        moved.update();
    }
    EXPECT_FALSE(moved.relocating());
    EXPECT_EQ(traced(moved), 1u);
    EXPECT_EQ(moved.cmos()[0].center, target);
    const gpu::Image &a = moved.cmoDistance(), &b = fresh.cmoDistance();
    for (uint32_t mip : {0u, a.desc().mips - 1})
        for (uint32_t layer = 0; layer < 6; ++layer)
            EXPECT_EQ(gpu::readImageRGBA(*ctx_, a.get(), a.desc(), VK_IMAGE_LAYOUT_GENERAL, mip, layer),
                      gpu::readImageRGBA(*ctx_, b.get(), b.desc(), VK_IMAGE_LAYOUT_GENERAL, mip, layer))
                << "mip " << mip << " face " << layer;
}
