// Local cubemap probes (SPECULUM_reflection_probe, kind local_cubemap): each probe's six faces
// are rendered by the renderer's own passes through a frame graph at the probe's resolution,
// GGX-prefiltered with the sky's prefilter (render::CubeFilter) and kept in one cube array that
// lives across frames. The module's entry point, Probes::addPasses, imports the array and the
// probe records into a frame graph and returns their handles; the reflections module takes
// them as inputs (its fallback chain: screen space, then these probes, then the sky). The
// module's README explains the technique, its failure modes and its settings.
#pragma once

#include "speculum/app/module.hpp"
#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/settings.hpp"

#include <glm/glm.hpp>

#include "probes/shaders/probe.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace speculum::probes {

// The module's settings table (probes.*, ProbeSettings::fields()).
std::vector<SettingDesc> settingsTable();
// What the module registers with its host.
app::ModuleInfo moduleInfo();

enum class DebugView : uint32_t { None = 0, Influence = 1, Winner = 2 };

// Filled by fromSettings<ProbeSettings>(); the defaults are the table's (the constructor writes
// them).
struct ProbeSettings {
    ProbeSettings();
    static const SettingFields<ProbeSettings>& fields();
    bool operator==(const ProbeSettings&) const = default;

    int bounces;           // bakes of every probe at start, each seeing the previous one
    int prefilterSamples;  // GGX samples per texel of the rough mips
    int prefilterSlice;    // time-sliced: prefilter work per update, in 1024 texel-samples
    int planarInterval;    // planar probes render every this many frames (renderPlanar)
    float planarScale;     // a planar image's height over the view's, where the probe sets none
    bool planarCrop;       // render only the texels a planar probe's rectangle covers on screen
    int planarGround;      // a planar probe's ground image size (0: none)
    bool autoProbe;        // an unconfigured scene gets a box probe fitted to its bounds
    int distanceSteps;     // march steps over a probe's captured distances (0: the proxy alone)
    DebugView debugView;
};


// A probe of the scene, as the module keeps it.
struct ProbeInfo {
    int node = -1;
    std::string name;
    ReflectionProbe probe;
    shader::Probe gpu{};  // the shader-visible record (probes/shaders/probe.h)
    float volume = 0.0f;  // world volume of the influence shape (smaller wins at equal order)
};

// The scene's CMOs (kind cmo) as the tracer reads them: arrays of six layers per CMO, each
// with a mip chain; a CMO below the largest resolution starts at the mip of its own size
// (modules/probes/shaders/cmo.h). All GENERAL between uses.
struct CmoSet {
    TextureHandle radiance;  // RGBA16F, cube-compatible: rgb lit radiance (box mips), a sun visibility + 2 mirror
    TextureHandle distance;  // RG32F: min, max world distance to the CMO's centre per cell (the hierarchy)
    TextureHandle attr;      // RGBA16F: xyz normal, w roughness (the G-buffer's)
    TextureHandle albedo;    // RGBA8: rgb base colour, a metallic
    BufferHandle records;    // CmoRecord[count], in trace order (higher `order` first)
    uint32_t count = 0;      // 0: none (or off); the handles still name valid arrays
};

// The planar probes (kind planar) rendered for this frame's view: one layer of a 2D array each,
// with box mips for glossy reflections. SHADER_READ-able (GENERAL between uses).
struct PlanarSet {
    TextureHandle images;  // RGBA16F 2D array: rgb the mirrored view's radiance, a the reflected distance (m)
    BufferHandle records;  // shader::PlanarProbe[count]
    uint32_t count = 0;    // 0: none faces this view (or off); the handles still name valid arrays
    // The planar probes' grounds (shader::PlanarGround; probes/shaders/ground.glsl), view-independent.
    TextureHandle ground;         // RGBA16F 2D array: rgb the plane's radiance premultiplied by a, its coverage
    BufferHandle groundRecords;   // shader::PlanarGround[groundCount]
    uint32_t groundCount = 0;     // 0: none (or off)
};

// What the module hands to the next one: valid handles in the graph they were added to.
struct ProbeSet {
    TextureHandle cubes;   // cube array, SHADER_READ_ONLY: cube i is probe i's prefiltered radiance
    TextureHandle distances;  // cube array, GENERAL: cube i is probe i's captured distance (RGBA16F, mip 0: r distance, gba mirror)
    BufferHandle records;  // shader::Probe[count], in blend order
    uint32_t count = 0;    // 0: no probe (or probes off); the handles still name valid dummies
    CmoSet cmos;           // invalid handles when the host did not add them
    PlanarSet planar;      // invalid handles when the host did not add them
};

// A CMO of the scene, as the module keeps it.
struct CmoInfo {
    int node = -1;
    std::string name;
    ReflectionProbe probe;
    glm::vec3 center{0.0f};
    uint32_t slot = 0;  // its six layers in the arrays start at 6 * slot
};

// A planar probe of the scene (kind planar), as the module keeps it.
struct PlanarInfo {
    int node = -1;
    std::string name;
    ReflectionProbe probe;
    glm::vec3 origin{0.0f}, axisX{1, 0, 0}, normal{0, 1, 0}, axisZ{0, 0, 1};  // world, orthonormal
    glm::vec4 plane{0.0f};  // normal, -dot(normal, origin)
};

// At most this many planar probes in a scene: each renders the scene once more per frame
// (depth prepass, G-buffer, lighting at its resolution), so four of them at the default half
// height cost about one more full-size engine frame.
inline constexpr size_t kMaxPlanarProbes = 4;

// The planar probe of a node: the node's origin lies on the plane, its local +Y is the normal
// (axes normalized: the node's scale does not scale the extents, which are metres).
PlanarInfo describePlanar(const Scene& scene, int node);
// The reflection in `plane` (xyz unit normal, w = -dot(normal, a point on it)) as an affine map.
glm::mat4 reflectionMatrix(glm::vec4 plane);
// `view` reflected in `plane`, at width x height, with an oblique near plane (Lengyel 2005,
// "Oblique View Frustum Depth Projection and Clipping", adapted to reversed-Z with an infinite
// far plane) `clipOffset` metres in front of the plane, so nothing on or behind the mirror is
// drawn. The plane's points project where `view` projects them (the reflection fixes them), so
// the planar image is read at the view's own UV. Returns false (camera untouched) when the view
// is orthographic or its eye is not in front of the plane.
bool mirroredCamera(const render::CameraState& view, glm::vec4 plane, uint32_t width, uint32_t height,
                    float clipOffset, render::CameraState& out);
// A rectangle of texels, [x0, x1) x [y0, y1).
struct TexelRect {
    uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x0 >= x1 || y0 >= y1; }
};
// The texels of a width x height image over `viewProj`'s screen that the planar probe's
// rectangle covers, as `viewProj` sees it (clipped at its near plane), grown by `margin` texels
// and clamped to the image; empty when none of the rectangle is on screen. The mirrored camera
// projects the plane's points where the view does, and a served pixel reads the planar image
// at its own screen position (a bumped or glossy one around it), so only these texels are read.
TexelRect planarFootprint(const glm::mat4& viewProj, const PlanarInfo& info, uint32_t width, uint32_t height,
                          uint32_t margin);
// The margin renderPlanar grows a footprint by: the widest lobe a planar probe serves (roughness
// 0.3, planarShare) reads a box mip of about 23 texels at the default half height, so a glossy
// pixel at the mirror's screen edge reads within 12 of it what the whole image would hold there.
inline constexpr uint32_t kPlanarCropMargin = 12;
// `camera`, whose image is width x height, restricted to `rect` of that image: its projection
// cropped (an off-axis window) so that the rect fills the returned camera's own image, each
// texel seeing along the same ray as the full camera's texel there.
render::CameraState cropCamera(const render::CameraState& camera, const TexelRect& rect);
// The orthographic camera of a planar probe's ground (probe.h, PlanarGround): straight down the
// normal from 50 m above the origin, the rectangle filling its size x size image, depth the plane
// +-2 cm. A point of the rectangle lands in clip x and y within [-1, 1], at depth 0.5.
render::CameraState groundCamera(const PlanarInfo& info, uint32_t size);

// Orders probes as the blend walks them: higher `order` first, then the smaller volume.
void sortForBlending(std::vector<ProbeInfo>& probes);
// The record of a probe node (world transform, shape, extents, blend distance).
ProbeInfo describeProbe(const Scene& scene, int node);
// The record of a probe at `world` (its centre and axes) that no node carries (node -1).
ProbeInfo describeProbe(const ReflectionProbe& probe, const glm::mat4& world, std::string name);
// probes.auto_probe: whether `scene` has no local cubemap probe of its own (a plain export, or
// one with only CMOs or planar probes, which sit above the local probes in the chain) and has
// bounds to fit one to, and then the box probe fitted to it (autoProbe's comment says how).
bool wantsAutoProbe(const Scene& scene);
ProbeInfo autoProbe(const Scene& scene);
// A probe's camera for cube face `face` (+X, -X, +Y, -Y, +Z, -Z), 90 degrees: the image's
// columns follow the Vulkan face's s axis and its rows the face's t axis after a vertical flip
// (the capture stores each face flipped: see capture.cpp).
render::CameraState faceCamera(glm::vec3 center, uint32_t face, uint32_t size, float znear = 0.05f);

class Probes {
public:
    // Validates the scene's local cubemap probes against the device: throws Error(BadInput)
    // naming the file, the node and the problem (resolution above the device's cube limit, more
    // probes than the cube array holds). Allocates the array; captures nothing yet.
    Probes(const gpu::Context& ctx, render::Renderer& renderer, const ProbeSettings& settings = {});
    ~Probes();
    Probes(const Probes&) = delete;
    Probes& operator=(const Probes&) = delete;

    // Captures what the update modes ask for this frame, in frame graphs of its own, submitted
    // and finished before it returns: call it before the frame's graph is built. `once` and
    // `on_demand` probes bake `bounces` times on the first call; `every_frame` probes capture all
    // six faces every call; `time_sliced` probes one face per call, in turn, then their
    // prefilter in steps of `probes.prefilter_slice` (render::planPrefilterSteps), one a call;
    // the array's cube changes mip by mip as the steps land (the old bake until then). `progress` (when set) hears about each face baked.
    using Progress = std::function<void(size_t done, size_t total)>;
    void update(const Progress& progress = {});
    // Updates a time-sliced probe takes from its first face to its prefiltered cube: six
    // captures and the prefilter's steps.
    size_t timeSlicedCycle() const;
    // A Progress that prints "probe bake (faces): done/total" on the terminal.
    static Progress terminalProgress();
    // Asks for a bake of one probe (index in blend order) or of all (-1) at the next update().
    void requestUpdate(int probe = -1);
    // Captures one probe (index in blend order; CMOs follow the local probes) or all (-1) again
    // from where it stands, spread over the next updates: a local probe runs the time-sliced
    // cycle (six faces, then the prefilter's steps; the old cube is blended until they land), a
    // CMO captures a face per update and rebuilds its hierarchy after the sixth, traced all the
    // while. What the game asks for when a gem is taken: requestUpdate(-1) re-baked the probe and
    // both CMOs of its level in one update (390-400 ms frames at 320x180 on lavapipe); this
    // spreads that work at about a face per frame.
    void recapture(int probe = -1);
    // Moves the local probe or CMO of scene node `node` to that node's new world transform
    // without rebuilding the module (the editor's live re-bake while a probe is dragged): its
    // faces are captured again one per update(), time-sliced, from the new place. A local
    // probe's record follows at once (its proxy moves, its cube is the old capture until the
    // prefilter's steps after the sixth face land, one per update); a CMO is left out of tracing until its six new faces and
    // hierarchy are done (its distances are relative to its centre). Moved again before the
    // sixth face, the cycle goes on and starts once more. False if the node has neither.
    bool moveProbe(int node, const glm::mat4& world);
    // Whether a moved probe or CMO is still being captured again.
    bool relocating() const;
    // Renders every planar probe whose plane faces `view`'s eye from the mirrored camera, in a
    // frame graph of its own, submitted and finished before it returns (call it before the
    // frame's graph runs, each frame: a planar image is view-dependent). The renderer keeps one
    // frame-constant buffer and a graph has one size, so the mirrored views cannot share the
    // frame's graph here; on a GPU they would, without the wait. With `interval` above 1 (the
    // setting probes.planar_interval) only every interval-th call renders; the others keep the
    // last images and their mirrored cameras, so that the reflection lags the camera by up to
    // interval - 1 frames (each pixel still projects into the camera its image was made with).
    void renderPlanar(const render::FrameInputs& view, int interval = 1);
    // Imports the cube array and the records into `graph` (count 0 when `enabled` is false), and
    // the CMO arrays (count 0 when `cmos` is false), and the planar images of the last
    // renderPlanar (count 0 when `enabled` is false).
    ProbeSet addPasses(FrameGraph& graph, bool enabled = true, bool cmos = true);
    // probes.debug: the blend or the winning probe per pixel (DebugView), scaled by 1 / exposure
    // like every debug view; returns the image that replaces the lit one.
    TextureHandle addDebugView(FrameGraph& graph, const render::GBuffer& gbuffer, const render::FrameInputs& frame,
                               const ProbeSet& set, DebugView view);

    const std::vector<ProbeInfo>& probes() const;
    // The scene's CMOs in trace order, and their arrays (tests).
    const std::vector<CmoInfo>& cmos() const;
    const gpu::Image& cmoDistance() const;
    const gpu::Image& cmoRadiance() const;
    // The cube array (tests): face size, mips, cubes.
    const gpu::Image& cubes() const;
    // The captured distances (tests): RGBA16F cube array at the cubes' face size, GENERAL.
    const gpu::Image& distances() const;
    // Local probes' faces captured so far and their total GPU milliseconds (the bench reports ms
    // per face); CMO faces are counted apart (cmoFacesCaptured, cmoCaptureMs).
    size_t facesCaptured() const;
    double captureMs() const;
    size_t cmoFacesCaptured() const;
    double cmoCaptureMs() const;
    // The scene's planar probes, and the GPU milliseconds of the last renderPlanar.
    const std::vector<PlanarInfo>& planars() const;
    double planarMs() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace speculum::probes
