// The module's frame-graph passes, in frame order. Pyramids are one pass per level (read level
// N - 1, write level N), so the graph derives every barrier between levels.
#include "module_impl.hpp"

#include "speculum/reflections/math.hpp"

#include <string>

namespace speculum::reflections {
namespace {

constexpr VkFormat kVisibilityFormat = VK_FORMAT_R8_UNORM;
constexpr VkFormat kColorFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kHitFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kGuideFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
// The reflected distance (m) the temporal pass reprojects by; r32f is a core storage format.
constexpr VkFormat kDistanceFormat = VK_FORMAT_R32_SFLOAT;

std::string levelName(const char* pass, uint32_t level) {
    return std::string("reflections.") + pass + "." + std::to_string(level);
}

// Mip 0 of the colour image `src` copied whole into mip 0 of `dst` (transfer layouts, as the graph put them).
void copyLevel0(PassContext& pc, TextureHandle src, TextureHandle dst) {
    VkExtent2D e = pc.extent(src);
    VkImageCopy copy{};
    copy.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.dstSubresource = copy.srcSubresource;
    copy.extent = {e.width, e.height, 1};
    vkCmdCopyImage(pc.cmd(), pc.image(src), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pc.image(dst),
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
}

}  // namespace

std::vector<TextureHandle> Reflections::Impl::addLitCopy(FrameGraph& g, const std::string& pass, TextureHandle lit,
                                                         const std::vector<CopyTarget>& targets) {
    struct Data {
        TextureHandle lit;
        std::vector<TextureHandle> dst;
    };
    const auto& d = g.addPass<Data>(
        pass, PassType::Transfer,
        [&](PassBuilder& b, Data& data) {
            data.lit = b.read(lit, TextureUsage::TransferSrc);
            for (const CopyTarget& t : targets)
                data.dst.push_back(b.write(t.into.valid() ? t.into : b.create(t.name, t.desc), TextureUsage::TransferDst,
                                           mipLevel(0)));
        },
        [](const Data& data, PassContext& pc) {
            for (TextureHandle dst : data.dst) copyLevel0(pc, data.lit, dst);
        });
    return d.dst;
}

std::vector<TextureHandle> Reflections::Impl::addClear(FrameGraph& g, const std::string& pass,
                                                       const std::vector<ClearTarget>& targets) {
    struct Data {
        std::vector<TextureHandle> dst;
    };
    const auto& d = g.addPass<Data>(
        pass, PassType::Transfer,
        [&](PassBuilder& b, Data& data) {
            for (const ClearTarget& t : targets)
                data.dst.push_back(b.write(b.create(t.name, t.desc), TextureUsage::TransferDst, mipLevel(0)));
        },
        [targets](const Data& data, PassContext& pc) {
            const VkImageSubresourceRange level0{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            for (size_t i = 0; i < data.dst.size(); ++i)
                vkCmdClearColorImage(pc.cmd(), pc.image(data.dst[i]), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                     &targets[i].value, 1, &level0);
        });
    return d.dst;
}

TextureHandle Reflections::Impl::addHiZ(FrameGraph& g, TextureHandle depth, uint32_t levels, TextureHandle& visibility) {
    historyHiz = g.importHistory("reflections.hiz", history.hiz.history());
    // Levels 0 and 1 and visibility level 1 in one pass (hiz_first.comp); a 1x1 view has level 0 only.
    struct FirstData {
        TextureHandle depth, level0, level1, visibility;
    };
    const bool two = levels > 1;
    const auto& first = g.addPass<FirstData>(
        levelName("hiz", 0), PassType::Compute,
        [&](PassBuilder& b, FirstData& data) {
            data.depth = b.read(depth, TextureUsage::Sampled);
            // Into the history pair's current image: its level 0 is the next frame's previous depth.
            data.level0 = b.write(historyHiz.current, TextureUsage::StorageWrite, mipLevel(0));
            if (!two) return;
            data.level1 = b.write(data.level0, TextureUsage::StorageWrite, mipLevel(1));
            TextureHandle vis = b.create("reflections.visibility", TextureDesc{.format = kVisibilityFormat, .mips = levels});
            data.visibility = b.write(vis, TextureUsage::StorageWrite, mipLevel(1));
        },
        [this, two](const FirstData& data, PassContext& pc) {
            gpu::DescriptorWriter w = writer();
            if (!two) {
                uint32_t level = 0;
                w.sampled("src", pc.view(data.depth), nearest).storage("dst", pc.view(data.level0, mipLevel(0)));
                dispatch(pc, hiz, w, pc.extent(data.level0, 0), &level, sizeof(level));
                return;
            }
            w.sampled("depthTex", pc.view(data.depth), nearest)
                .storage("level0", pc.view(data.level1, mipLevel(0)))
                .storage("level1", pc.view(data.level1, mipLevel(1)))
                .storage("visibility1", pc.view(data.visibility, mipLevel(1)));
            dispatch(pc, hizFirst, w, pc.extent(data.level1, 1));
        });
    visibility = first.visibility;
    TextureHandle pyramid = two ? first.level1 : first.level0;
    struct Data {
        TextureHandle src, dst;
        uint32_t level;
    };
    for (uint32_t level = 2; level < levels; ++level) {
        const auto& d = g.addPass<Data>(
            levelName("hiz", level), PassType::Compute,
            [&](PassBuilder& b, Data& data) {
                data.level = level;
                data.src = b.read(pyramid, TextureUsage::Sampled, mipLevel(level - 1));
                data.dst = b.write(pyramid, TextureUsage::StorageWrite, mipLevel(level));
            },
            [this](const Data& data, PassContext& pc) {
                gpu::DescriptorWriter w;  // hiz.comp reads no frame constants
                w.sampled("src", pc.view(data.src, mipLevel(data.level - 1)), nearest)
                    .storage("dst", pc.view(data.dst, mipLevel(data.level)));
                dispatch(pc, hiz, w, pc.extent(data.dst, data.level), &data.level, sizeof(uint32_t));
            });
        pyramid = d.dst;
    }
    return pyramid;
}

TextureHandle Reflections::Impl::addVisibility(FrameGraph& g, TextureHandle hizPyramid, TextureHandle level1,
                                               uint32_t levels) {
    struct Data {
        TextureHandle hiz, src, dst;
        uint32_t level;
    };
    // Level 0 is fully visible by definition and nothing reads it (the colour pyramid's level 0
    // carries 1 in alpha, and level 1 assumes it): it is never written, one full-resolution
    // pass less (issue 13, "cheaper fixed cost"). Level 1 comes from reflections.hiz.0.
    TextureHandle pyramid = level1;
    for (uint32_t level = 2; level < levels; ++level) {
        const auto& d = g.addPass<Data>(
            levelName("visibility", level), PassType::Compute,
            [&](PassBuilder& b, Data& data) {
                data.level = level;
                data.hiz = b.read(hizPyramid, TextureUsage::Sampled);
                data.src = b.read(pyramid, TextureUsage::Sampled, mipLevel(level - 1));
                data.dst = b.write(pyramid, TextureUsage::StorageWrite, mipLevel(level));
            },
            [this](const Data& data, PassContext& pc) {
                gpu::DescriptorWriter w = writer();
                w.sampled("hiz", pc.view(data.hiz), nearest)
                    .sampled("fineVis", pc.view(data.src, mipLevel(data.level - 1)), nearest)
                    .storage("dst", pc.view(data.dst, mipLevel(data.level)));
                dispatch(pc, visibility, w, pc.extent(data.dst, data.level), &data.level, sizeof(uint32_t));
            });
        pyramid = d.dst;
    }
    return pyramid;
}

// reflections.reproject: colour level 0 from the previous final image (reproject.comp), over
// `copied` (the lit copy) on the reflective tiles with tiles, else on every pixel.
TextureHandle Reflections::Impl::addReproject(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                              const ReflectionSettings& s, TextureHandle copied,
                                              const TextureDesc& pyramidDesc) {
    struct ReprojectData {
        TextureHandle depth, motion, lit, emissive, historyColor, historyDepth, dst;
        BufferHandle tiles, footprint;
    };
    const auto& r = g.addPass<ReprojectData>(
        "reflections.reproject", PassType::Compute,
        [&](PassBuilder& b, ReprojectData& d) {
            d.depth = b.read(in.gbuffer.depth, TextureUsage::Sampled);
            d.motion = b.read(in.gbuffer.motion, TextureUsage::Sampled);
            d.lit = b.read(in.lit, TextureUsage::Sampled);
            d.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            d.historyColor = b.read(historyColor.previous, TextureUsage::Sampled);
            d.historyDepth = b.read(historyHiz.previous, TextureUsage::Sampled, mipLevel(0));
            d.tiles = b.read(tiles.tiles, BufferUsage::StorageRead);
            // At half resolution a workgroup a block of the footprint (reflections.footprint_args),
            // in the order tiles.glsl's footprintBlockPixel gives them.
            if (s.tiles && tiles.footprint.valid())
                d.footprint = b.read(tiles.footprint, BufferUsage::Indirect);
            else if (s.tiles)
                b.read(tiles.tiles, BufferUsage::Indirect);
            d.dst = b.write(copied.valid() ? copied : b.create("reflections.color", pyramidDesc),
                            TextureUsage::StorageWrite, mipLevel(0));
        },
        [this, tiled = s.tiles, half = tiles.guide.valid()](const ReprojectData& d, PassContext& pc) {
            gpu::DescriptorWriter w = writer();
            w.sampled("depthTex", pc.view(d.depth), nearest)
                .sampled("motionTex", pc.view(d.motion), nearest)
                .sampled("litTex", pc.view(d.lit), nearest)
                .sampled("emissiveTex", pc.view(d.emissive), nearest)
                .buffer("MaterialTable", materials.get())
                .sampled("historyColor", pc.view(d.historyColor), trilinear)
                .sampled("historyDepth", pc.view(d.historyDepth, mipLevel(0)), nearest)
                .storage("dst", pc.view(d.dst, mipLevel(0)))
                .buffer("tiles", pc.buffer(d.tiles));
            using namespace shader;
            const uint32_t work = tiled ? kTileModeWork : kTileModeScreen;
            dispatchTiles(pc, w, d.tiles, tiled,
                          {{&reproject(work, half, kListResolveRay), kListResolveRay},
                           {&reproject(kTileModeWork, half, kListLookup), kListLookup}},
                          pc.extent(d.dst, 0), d.footprint);
        });
    return r.dst;
}

TextureHandle Reflections::Impl::addColorPyramid(FrameGraph& g, const ReflectionInputs& in, TextureHandle visibility,
                                                 uint32_t levels, const Classified& tiles, const ReflectionSettings& s) {
    historyColor = g.importHistory("reflections.history.color", history.color.history());
    // With tiles, level 0 starts as the lit image (what every pixel that does not reflect gets),
    // copied whole, and the reprojection overwrites the reflective tiles.
    const TextureDesc pyramidDesc{.format = kColorFormat, .mips = levels};
    // Without multi_bounce the reprojection gives every pixel the lit image: the copy alone is the
    // same bits (3.5 of low's 48 ms at 330x256 on lavapipe, 19 ms at 960x540 fully reflective).
    const bool reprojects = s.multiBounce;
    TextureHandle copied = s.tiles || !reprojects ? addLitCopy(g, "reflections.reproject_copy", in.lit,
                                                               {{"reflections.color", pyramidDesc, {}}})[0]
                                                  : TextureHandle{};
    TextureHandle pyramid = copied;
    if (reprojects) pyramid = addReproject(g, in, tiles, s, copied, pyramidDesc);
    // Each level also carries the visibility pyramid's level in alpha (level 0: 1, as reproject
    // writes): the cone trace then gets colour and visibility from one trilinear lookup.
    struct DownData {
        TextureHandle src, visibility, dst;
        uint32_t level;
    };
    for (uint32_t level = 1; level < levels; ++level) {
        const auto& d = g.addPass<DownData>(
            levelName("color_pyramid", level), PassType::Compute,
            [&](PassBuilder& b, DownData& data) {
                data.level = level;
                data.src = b.read(pyramid, TextureUsage::Sampled, mipLevel(level - 1));
                data.visibility = b.read(visibility, TextureUsage::Sampled, mipLevel(level));
                data.dst = b.write(pyramid, TextureUsage::StorageWrite, mipLevel(level));
            },
            [this](const DownData& data, PassContext& pc) {
                gpu::DescriptorWriter w;  // color_down.comp reads no frame constants
                w.sampled("src", pc.view(data.src, mipLevel(data.level - 1)), trilinear)
                    .storage("dst", pc.view(data.dst, mipLevel(data.level)))
                    .sampled("visibilityLevel", pc.view(data.visibility, mipLevel(data.level)), nearest);
                dispatch(pc, colorDown, w, pc.extent(data.dst, data.level));
            });
        pyramid = d.dst;
    }
    return pyramid;
}

Reflections::Impl::Classified Reflections::Impl::addClassify(FrameGraph& g, const ReflectionInputs& in,
                                                            TextureHandle hizPyramid, const ReflectionSettings& s) {
    const bool half = s.resolution == Resolution::Half;
    // One workgroup (tile) per 8x8 pixels of the trace's size; every tile appends to one list per
    // pass, so a list holds at most every tile.
    const uint32_t w = g.config().outputWidth, h = g.config().outputHeight;
    const uint32_t traceW = half ? (w + 1) / 2 : w, traceH = half ? (h + 1) / 2 : h;
    const uint32_t tileCount = ((traceW + shader::kTileSize - 1) / shader::kTileSize) *
                               ((traceH + shader::kTileSize - 1) / shader::kTileSize);
    const VkDeviceSize headerBytes = shader::kTileLists * sizeof(glm::uvec4);
    struct ClearData {
        BufferHandle tiles;
    };
    const auto& clear = g.addPass<ClearData>(
        "reflections.tile_clear", PassType::Transfer,
        [&](PassBuilder& b, ClearData& d) {
            BufferHandle tiles = b.create(
                "reflections.tiles", BufferDesc{headerBytes + VkDeviceSize(tileCount) * shader::kTileLists * sizeof(uint32_t)});
            d.tiles = b.write(tiles, BufferUsage::TransferDst);
        },
        [headerBytes](const ClearData& d, PassContext& pc) {
            // Each list's dispatch: 0 tiles, y = z = 1 (classify counts x up).
            std::array<glm::uvec4, shader::kTileLists> header;
            header.fill(glm::uvec4(0u, 1u, 1u, 0u));
            vkCmdUpdateBuffer(pc.cmd(), pc.buffer(d.tiles), 0, headerBytes, header.data());
            // The entries, for the arrival words (tiles.h, kListArrivals).
            vkCmdFillBuffer(pc.cmd(), pc.buffer(d.tiles), headerBytes, VK_WHOLE_SIZE, 0u);
        });
    struct Data {
        TextureHandle hiz, normal, emissive, guide, planar;
        BufferHandle planarRecords, tiles;
    };
    const auto& d = g.addPass<Data>(
        "reflections.classify", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.planar = b.read(in.probes.planar.images, TextureUsage::Sampled);
            data.planarRecords = b.read(in.probes.planar.records, BufferUsage::StorageRead);
            data.hiz = b.read(hizPyramid, TextureUsage::Sampled);
            data.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
            data.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            data.tiles = b.write(clear.tiles, BufferUsage::StorageWrite);
            // Full resolution writes no guide: a 1x1 image stands in for the binding (unwritten).
            TextureDesc desc{.relativeScale = 0.5f, .format = kGuideFormat, .relativeTo = in.gbuffer.depth};
            if (!half) desc = {.width = 1, .height = 1, .format = kGuideFormat};
            data.guide = b.write(b.create(half ? "reflections.guide" : "reflections.no_guide", desc),
                                 TextureUsage::StorageWrite);
        },
        [this, half, traceW, traceH, budget = s.rayBudget](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = surfaceWriter(pc, data.hiz, data.normal, data.emissive);
            w.buffer("tiles", pc.buffer(data.tiles))
                .storage("guideOut", pc.view(data.guide))
                .buffer("PlanarBuffer", pc.buffer(data.planarRecords))
                .sampled("planarImages", pc.view(data.planar, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), trilinear);
            dispatch(pc, classify(half ? Resolution::Half : Resolution::Full, budget), w, {traceW, traceH});
        });
    if (!half || !s.tiles) return {d.tiles, half ? d.guide : TextureHandle{}};
    return {d.tiles, d.guide, addFootprintArgs(g, d.tiles)};
}

// reflections.footprint_args: at half resolution a tile of the trace is a 16x16 footprint of the
// full-resolution passes (reflections.reproject, reflections.composite), and these dispatches
// give each of its four 8x8 blocks a workgroup of its own (y = 4; tiles.glsl's
// footprintBlockPixel orders them so that one footprint's blocks run together, which took the
// composite at half from 16.8 to 11.6 ms on closed_room.main, MEASUREMENTS.md issue 23). The
// lists' counts are copied from classify's headers; y, z and the padding are written around
// them, so the two writes never overlap.
BufferHandle Reflections::Impl::addFootprintArgs(FrameGraph& g, BufferHandle classified, bool cmoList) {
    struct Data {
        BufferHandle tiles, args;
    };
    // Slots in kFootprintLists' order; the CMO list's own buffer (after reflections.trace, which
    // appends to that list) fills its slot alone.
    const auto& d = g.addPass<Data>(
        cmoList ? "reflections.footprint_cmo_args" : "reflections.footprint_args", PassType::Transfer,
        [&](PassBuilder& b, Data& data) {
            data.tiles = b.read(classified, BufferUsage::TransferSrc);
            data.args = b.write(b.create(cmoList ? "reflections.footprint_cmo" : "reflections.footprint",
                                         BufferDesc{kFootprintLists.size() * sizeof(glm::uvec4)}),
                                BufferUsage::TransferDst);
        },
        [cmoList](const Data& data, PassContext& pc) {
            const uint32_t rest[3] = {4u, 1u, 0u};  // y: the four 8x8 blocks of a footprint
            for (uint32_t slot = 0; slot < kFootprintLists.size(); ++slot) {
                if ((kFootprintLists[slot] == shader::kListCmo) != cmoList) continue;
                const VkDeviceSize at = slot * sizeof(glm::uvec4);
                vkCmdUpdateBuffer(pc.cmd(), pc.buffer(data.args), at + sizeof(uint32_t), sizeof rest, rest);
                VkBufferCopy count{kFootprintLists[slot] * sizeof(glm::uvec4), at, sizeof(uint32_t)};
                vkCmdCopyBuffer(pc.cmd(), pc.buffer(data.tiles), pc.buffer(data.args), 1, &count);
            }
        });
    return d.args;
}

TextureHandle Reflections::Impl::addTrace(FrameGraph& g, const ReflectionInputs& in, TextureHandle hizPyramid,
                                          Classified& tiles, const ReflectionSettings& s) {
    struct Data {
        TextureHandle hiz, normal, emissive, guide, hit, planar;
        BufferHandle planarRecords, tiles;
    };
    const Resolution res = s.resolution;
    TextureDesc desc{.format = kHitFormat};
    if (res == Resolution::Half) desc.relativeTo = tiles.guide;
    // With tiles, every pixel starts as trace.comp's "not traced" and the trace writes its ray
    // tiles only.
    const TextureHandle cleared =
        s.tiles ? addClear(g, "reflections.trace_clear", {{"reflections.hit", desc, {{-1.0f, -1.0f, -1.0f, 0.0f}}}})[0]
                : TextureHandle{};
    const auto& d = g.addPass<Data>(
        "reflections.trace", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.planar = b.read(in.probes.planar.images, TextureUsage::Sampled);
            data.planarRecords = b.read(in.probes.planar.records, BufferUsage::StorageRead);
            data.hiz = b.read(hizPyramid, TextureUsage::Sampled);
            data.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
            data.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            // It reads its own lists and appends its tiles to the CMO trace's (trace.comp).
            b.read(tiles.tiles, BufferUsage::Indirect);
            data.tiles = tiles.tiles = b.write(tiles.tiles, BufferUsage::StorageWrite);
            // Full resolution binds the normals in the guide's place (unread).
            if (res == Resolution::Half) data.guide = b.read(tiles.guide, TextureUsage::Sampled);
            data.hit = b.write(cleared.valid() ? cleared : b.create("reflections.hit", desc), TextureUsage::StorageWrite);
        },
        [this, mode = s.trace, res, glossy = s.glossy, tiled = s.tiles](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = surfaceWriter(pc, data.hiz, data.normal, data.emissive);
            w.storage("hitOut", pc.view(data.hit))
                .sampled("guideTex", pc.view(data.guide.valid() ? data.guide : data.normal), nearest)
                .buffer("tiles", pc.buffer(data.tiles))
                .buffer("PlanarBuffer", pc.buffer(data.planarRecords))
                .sampled("planarImages", pc.view(data.planar, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), trilinear);
            using namespace shader;
            dispatchTiles(pc, w, data.tiles, tiled,
                          {{&trace(mode, res, glossy, tiled ? kTileModeWork : kTileModeScreen), kListTrace}},
                          pc.extent(data.hit));
        });
    return d.hit;
}

void Reflections::Impl::addCmoTrace(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                    const ReflectionSettings& s, ReflectionOutputs& out) {
    const probes::CmoSet& set = in.probes.cmos;
    const TextureHandle guideImage = tiles.guide;
    struct Data {
        TextureHandle hiz, normal, emissive, hit, guide, cmo, info, planar;
        BufferHandle planarRecords, tiles;
        CmoReads cmos;
    };
    const TextureDesc desc{.format = kColorFormat, .relativeTo = out.hit};
    // With tiles, both outputs start as 0 ("no CMO hit") and the CMO trace writes its tiles only.
    std::vector<TextureHandle> cleared;
    if (s.tiles)
        cleared = addClear(g, "reflections.cmo_clear",
                           {{"reflections.cmo", desc, {{0.0f, 0.0f, 0.0f, 0.0f}}},
                            {"reflections.cmo_info", desc, {{0.0f, 0.0f, 0.0f, 0.0f}}}});
    const auto& d = g.addPass<Data>(
        "reflections.cmo_trace", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.planar = b.read(in.probes.planar.images, TextureUsage::Sampled);
            data.planarRecords = b.read(in.probes.planar.records, BufferUsage::StorageRead);
            data.hiz = b.read(out.hiz, TextureUsage::Sampled);
            data.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
            data.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            data.hit = b.read(out.hit, TextureUsage::Sampled);
            data.guide = b.read(guideImage.valid() ? guideImage : in.gbuffer.normal, TextureUsage::Sampled);
            data.cmos = readCmos(b, set);
            data.tiles = b.read(tiles.tiles, BufferUsage::StorageRead);
            b.read(tiles.tiles, BufferUsage::Indirect);
            data.cmo = b.write(cleared.empty() ? b.create("reflections.cmo", desc) : cleared[0], TextureUsage::StorageWrite);
            data.info = b.write(cleared.empty() ? b.create("reflections.cmo_info", desc) : cleared[1],
                                TextureUsage::StorageWrite);
        },
        [this, half = guideImage.valid(), linear = s.cmoTrace == CmoTraceMode::Linear, tiled = s.tiles](
            const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = surfaceWriter(pc, data.hiz, data.normal, data.emissive);
            bindCmos(w, pc, data.cmos);
            w.sampled("hitTex", pc.view(data.hit), nearest)
                .sampled("guideTex", pc.view(data.guide), nearest)
                .storage("cmoOut", pc.view(data.cmo))
                .storage("infoOut", pc.view(data.info))
                .buffer("PlanarBuffer", pc.buffer(data.planarRecords))
                .sampled("planarImages", pc.view(data.planar, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), trilinear)
                .buffer("tiles", pc.buffer(data.tiles));
            using namespace shader;
            const Resolution res = half ? Resolution::Half : Resolution::Full;
            dispatchTiles(pc, w, data.tiles, tiled,
                          {{&cmoTrace(res, linear, tiled ? kTileModeWork : kTileModeScreen), kListCmo}},
                          pc.extent(data.cmo));
        });
    out.cmo = d.cmo;
    out.cmoInfo = d.info;
}

// The probe sets are the host's, or the dummies Reflections::addPasses imports when it gave none.
Reflections::Impl::ChainReads Reflections::Impl::readChain(PassBuilder& b, const probes::ProbeSet& set) {
    return {b.read(set.cubes, TextureUsage::Sampled), b.read(set.planar.images, TextureUsage::Sampled),
            b.read(set.planar.ground, TextureUsage::Sampled), b.read(set.distances, TextureUsage::Sampled),
            b.read(set.records, BufferUsage::StorageRead), b.read(set.planar.records, BufferUsage::StorageRead),
            b.read(set.planar.groundRecords, BufferUsage::StorageRead)};
}

void Reflections::Impl::bindChain(gpu::DescriptorWriter& w, PassContext& pc, const ChainReads& r) const {
    const render::Environment& env = renderer.environment();
    w.sampled("envSpecular", env.specular().view(), env.sampler())
        .buffer("ProbeBuffer", pc.buffer(r.probeRecords))
        .sampled("probeCubes", pc.view(r.probeCubes, {}, VK_IMAGE_VIEW_TYPE_CUBE_ARRAY), trilinear)
        // Nearest: a bilinear distance at a silhouette blends the near surface with the far one,
        // and the march then finds neither (cornell_mirrors' rough band lost its +1.7 dB that way).
        .sampled("probeDistance", pc.view(r.probeDistances, {}, VK_IMAGE_VIEW_TYPE_CUBE_ARRAY), nearest)
        .buffer("PlanarBuffer", pc.buffer(r.planarRecords))
        .sampled("planarImages", pc.view(r.planar, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), trilinear)
        .buffer("GroundBuffer", pc.buffer(r.groundRecords))
        .sampled("groundImages", pc.view(r.ground, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), trilinear);
}

// A CMO set as the passes that trace or shade its hits read it (cmo_trace, hit_reuse_cmo).
Reflections::Impl::CmoReads Reflections::Impl::readCmos(PassBuilder& b, const probes::CmoSet& set) {
    return {b.read(set.distance, TextureUsage::Sampled), b.read(set.radiance, TextureUsage::Sampled),
            b.read(set.attr, TextureUsage::Sampled), b.read(set.albedo, TextureUsage::Sampled),
            b.read(set.records, BufferUsage::StorageRead)};
}

void Reflections::Impl::bindCmos(gpu::DescriptorWriter& w, PassContext& pc, const CmoReads& r) const {
    w.buffer("CmoBuffer", pc.buffer(r.records))
        .sampled("cmoDistance", pc.view(r.distance, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), nearest)
        .sampled("cmoLayers", pc.view(r.radiance, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), nearest)
        .sampled("cmoAttr", pc.view(r.attr, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), nearest)
        .sampled("cmoAlbedo", pc.view(r.albedo, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), nearest)
        .sampled("cmoRadiance", pc.view(r.radiance, {}, VK_IMAGE_VIEW_TYPE_CUBE_ARRAY), trilinear);
}

void Reflections::Impl::addResolve(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                   const ReflectionSettings& s, ReflectionOutputs& out) {
    const TextureHandle guideImage = tiles.guide;
    struct Data {
        TextureHandle hiz, normal, emissive, hit, color, guide, reflection, method, distance, cmo, lit, albedo, shadow;
        BufferHandle tiles;
        ChainReads chain;
    };
    const auto& d = g.addPass<Data>(
        "reflections.resolve", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.chain = readChain(b, in.probes);
            data.tiles = b.read(tiles.tiles, BufferUsage::StorageRead);
            b.read(tiles.tiles, BufferUsage::Indirect);
            data.hiz = b.read(out.hiz, TextureUsage::Sampled);
            data.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
            data.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            data.hit = b.read(out.hit, TextureUsage::Sampled);
            data.color = b.read(out.colorPyramid, TextureUsage::Sampled);
            // Mirror hits are shaded for the ray (resolve.comp, mirrorHit): the hit's lit colour and material.
            data.lit = b.read(in.lit, TextureUsage::Sampled);
            data.albedo = b.read(in.gbuffer.albedo, TextureUsage::Sampled);
            // Without a directional light there is no mask (unread then: the normals in its place).
            data.shadow = b.read(in.gbuffer.shadowMask.valid() ? in.gbuffer.shadowMask : in.gbuffer.normal,
                                 TextureUsage::Sampled);
            data.guide = b.read(guideImage.valid() ? guideImage : in.gbuffer.normal, TextureUsage::Sampled);
            // At the trace's size (half: the guide's).
            TextureDesc desc{.format = kColorFormat, .relativeTo = out.hit};
            bool half = guideImage.valid();
            data.reflection = b.write(b.create(half ? "reflections.reflection_half" : "reflections.reflection", desc),
                                      TextureUsage::StorageWrite);
            data.method = b.write(b.create(half ? "reflections.method_half" : "reflections.method", desc),
                                  TextureUsage::StorageWrite);
            data.distance = b.write(b.create("reflections.distance", {.format = kDistanceFormat, .relativeTo = out.hit}),
                                    TextureUsage::StorageWrite);
            // Without CMOs the hit image is bound in the CMO result's place (unread: rf.cmoCount 0).
            data.cmo = b.read(out.cmo.valid() ? out.cmo : out.hit, TextureUsage::Sampled);
        },
        [this, res = guideImage.valid() ? Resolution::Half : Resolution::Full, glossy = s.glossy,
         tiled = s.tiles](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = surfaceWriter(pc, data.hiz, data.normal, data.emissive);
            bindChain(w, pc, data.chain);
            w.sampled("hitTex", pc.view(data.hit), nearest)
                .sampled("colorPyramid", pc.view(data.color), trilinear)
                .sampled("guideTex", pc.view(data.guide), nearest)
                .storage("reflectionOut", pc.view(data.reflection))
                .storage("methodOut", pc.view(data.method))
                .sampled("cmoTex", pc.view(data.cmo), nearest)
                .storage("distanceOut", pc.view(data.distance))
                .sampled("litTex", pc.view(data.lit), nearest)
                .sampled("albedoTex", pc.view(data.albedo), nearest)
                .sampled("dfgTex", renderer.environment().dfg().view(), renderer.environment().sampler())
                .sampled("shadowMaskTex", pc.view(data.shadow), nearest)
                .buffer("tiles", pc.buffer(data.tiles));
            using namespace shader;
            // The resolve's own lists split the ray and lookup tiles by what their lobes need
            // (tiles.h): each variant compiles out what none of its tiles' pixels runs.
            dispatchTiles(pc, w, data.tiles, tiled,
                          {{&resolve(res, glossy, tiled ? kTileModeWork : kTileModeScreen), kListResolveCone},
                           {&resolve(res, glossy, kTileModeMirror), kListResolveMirror},
                           {&resolve(res, glossy, kTileModeLookup), kListLookupNarrow},
                           {&resolve(res, glossy, kTileModeRough), kListLookupRough},
                           {&resolve(res, glossy, kTileModeFill), kListResolveFill}},
                          pc.extent(data.reflection));
        });
    out.reflection = d.reflection;
    out.method = d.method;
    out.distance = d.distance;
}

// reflections.lookup_full (lookup_full.comp): over the upsampled reflection, on the reflective
// tiles' footprints, else over the whole screen.
TextureHandle Reflections::Impl::addLookupFull(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                               const ReflectionSettings& s, TextureHandle hizPyramid,
                                               TextureHandle halfMethod, TextureHandle upsampled) {
    struct Data {
        TextureHandle hiz, normal, emissive, method, dst;
        BufferHandle tiles, footprint;
        ChainReads chain;
    };
    const auto& d = g.addPass<Data>(
        "reflections.lookup_full", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.hiz = b.read(hizPyramid, TextureUsage::Sampled);
            data.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
            data.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            data.method = b.read(halfMethod, TextureUsage::Sampled);
            data.chain = readChain(b, in.probes);
            data.tiles = b.read(tiles.tiles, BufferUsage::StorageRead);
            if (s.tiles) data.footprint = b.read(tiles.footprint, BufferUsage::Indirect);
            data.dst = b.write(upsampled, TextureUsage::StorageWrite);
        },
        [this, tiled = s.tiles](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = surfaceWriter(pc, data.hiz, data.normal, data.emissive);
            bindChain(w, pc, data.chain);
            w.sampled("methodTex", pc.view(data.method), nearest)
                .storage("reflectionOut", pc.view(data.dst))
                .buffer("tiles", pc.buffer(data.tiles));
            using namespace shader;
            // A pixel with lookups reflects, so its tile is in one of the two reflective lists.
            dispatchTiles(pc, w, data.tiles, tiled,
                          {{&lookupFull(tiled ? kTileModeWork : kTileModeScreen, kListResolveRay), kListResolveRay},
                           {&lookupFull(kTileModeWork, kListLookup), kListLookup}},
                          pc.extent(data.dst), data.footprint);
        });
    return d.dst;
}

// reflections.hit_reuse (hit_reuse.glsl): over the upsampled reflection, screen space's and the
// sky's hits on the reflective tiles' footprints; with CMOs traced, then
// reflections.hit_reuse_cmo, the CMOs' too, on the CMO tiles' footprints only (a pixel takes a CMO
// hit only where its own 2x2's sample was a CMO's, whose tile is on that list). Lavapipe pays a
// pass's whole code on every pixel it is dispatched on, and the CMO variant is four times the
// other's (MEASUREMENTS.md, issue 23, "hit reuse"). Without tiles, the CMO variant over the whole
// screen alone: the same values.
TextureHandle Reflections::Impl::addHitReuse(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                             const ReflectionSettings& s, const ReflectionOutputs& out,
                                             TextureHandle halfMethod, TextureHandle halfReflection,
                                             TextureHandle upsampled) {
    const bool cmos = out.cmo.valid();
    const bool linear = s.cmoTrace == CmoTraceMode::Linear;
    if (!s.tiles) return addHitReusePass(g, in, tiles, out, halfMethod, halfReflection, upsampled, cmos, linear, {});
    TextureHandle reused =
        addHitReusePass(g, in, tiles, out, halfMethod, halfReflection, upsampled, false, linear, tiles.footprint);
    if (!cmos) return reused;
    const BufferHandle cmoFootprint = addFootprintArgs(g, tiles.tiles, true);
    return addHitReusePass(g, in, tiles, out, halfMethod, halfReflection, reused, true, linear, cmoFootprint);
}

TextureHandle Reflections::Impl::addHitReusePass(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                                 const ReflectionOutputs& out, TextureHandle halfMethod,
                                                 TextureHandle halfReflection, TextureHandle upsampled, bool cmos,
                                                 bool linear, BufferHandle footprint) {
    const probes::CmoSet& set = in.probes.cmos;
    struct Data {
        TextureHandle hiz, normal, emissive, hit, color, guide, method, half, dst, cmo, info;
        BufferHandle tiles, footprint;
        CmoReads cmos;
    };
    const auto& d = g.addPass<Data>(
        cmos ? "reflections.hit_reuse_cmo" : "reflections.hit_reuse", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.hiz = b.read(out.hiz, TextureUsage::Sampled);
            data.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
            data.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            data.hit = b.read(out.hit, TextureUsage::Sampled);
            data.color = b.read(out.colorPyramid, TextureUsage::Sampled);
            data.guide = b.read(tiles.guide, TextureUsage::Sampled);
            data.method = b.read(halfMethod, TextureUsage::Sampled);
            data.half = b.read(halfReflection, TextureUsage::Sampled);
            data.tiles = b.read(tiles.tiles, BufferUsage::StorageRead);
            if (footprint.valid()) data.footprint = b.read(footprint, BufferUsage::Indirect);
            if (cmos) {
                data.cmo = b.read(out.cmo, TextureUsage::Sampled);
                data.info = b.read(out.cmoInfo, TextureUsage::Sampled);
                data.cmos = readCmos(b, set);
            }
            data.dst = b.write(upsampled, TextureUsage::StorageWrite);
        },
        [this, cmos, linear](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = surfaceWriter(pc, data.hiz, data.normal, data.emissive);
            w.sampled("hitTex", pc.view(data.hit), nearest)
                .sampled("colorPyramid", pc.view(data.color), trilinear)
                .sampled("guideTex", pc.view(data.guide), nearest)
                .sampled("methodTex", pc.view(data.method), nearest)
                .sampled("halfTex", pc.view(data.half), nearest)
                .sampled("envSpecular", renderer.environment().specular().view(), renderer.environment().sampler())
                .storage("reflectionOut", pc.view(data.dst))
                .buffer("tiles", pc.buffer(data.tiles));
            if (cmos) {
                bindCmos(w, pc, data.cmos);
                w.sampled("cmoTex", pc.view(data.cmo), nearest).sampled("cmoInfoTex", pc.view(data.info), nearest);
            }
            using namespace shader;
            const bool tiled = data.footprint.valid();
            if (!tiled)
                dispatchTiles(pc, w, data.tiles, false, {{&hitReuse(kTileModeScreen, cmos, linear, 0), 0}},
                              pc.extent(data.dst));
            else if (cmos)
                dispatchTiles(pc, w, data.tiles, true, {{&hitReuse(kTileModeWork, true, linear, kListCmo), kListCmo}},
                              pc.extent(data.dst), data.footprint);
            else  // a pixel the sky answered may lie in a tile without a screen-space ray
                dispatchTiles(pc, w, data.tiles, true,
                              {{&hitReuse(kTileModeWork, false, linear, kListResolveRay), kListResolveRay},
                               {&hitReuse(kTileModeWork, false, linear, kListLookup), kListLookup}},
                              pc.extent(data.dst), data.footprint);
        });
    return d.dst;
}

TextureHandle Reflections::Impl::addComposite(FrameGraph& g, const ReflectionInputs& in, const ReflectionOutputs& out,
                                              const Classified& tiles, const ReflectionSettings& s, TextureHandle raw) {
    const DebugView view = s.debugView;
    const bool separate = view != DebugView::None || raw.valid();
    // Work follows need: with tiles and no debug view (a debug view draws every pixel) the
    // composite runs on the reflective tiles only, into outputs that hold the lit image already.
    const CompositeVariant variant{view, raw.valid(), s.tiles && view == DebugView::None, tiles.guide.valid()};
    const TextureDesc litDesc{.format = render::kLinearFormat};
    TextureHandle copiedDst, copiedPlain;
    if (variant.tiled) {
        // The image the next frame reprojects is written in place in the colour history.
        std::vector<CopyTarget> targets{{"reflections.lit", litDesc, separate ? TextureHandle{} : historyColor.current}};
        if (separate) targets.push_back({"reflections.lit_plain", litDesc, historyColor.current});
        std::vector<TextureHandle> copied = addLitCopy(g, "reflections.composite_copy", in.lit, targets);
        copiedDst = copied[0];
        if (separate) copiedPlain = copied[1];
    }
    struct Data {
        TextureHandle lit, albedo, normal, emissive, reflection, raw, hiz, hit, debug, dst, plain;
        BufferHandle tiles, footprint;
    };
    const auto& d = g.addPass<Data>(
        "reflections.composite", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.lit = b.read(in.lit, TextureUsage::Sampled);
            data.tiles = b.read(tiles.tiles, BufferUsage::StorageRead);  // the tiles debug view, the tiled dispatch
            if (variant.tiled && tiles.footprint.valid())
                data.footprint = b.read(tiles.footprint, BufferUsage::Indirect);
            else if (variant.tiled)
                b.read(tiles.tiles, BufferUsage::Indirect);
            data.albedo = b.read(in.gbuffer.albedo, TextureUsage::Sampled);
            data.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
            data.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
            data.reflection = b.read(out.reflection, TextureUsage::Sampled);
            // Without temporal accumulation the reflection is bound in raw's place (unread).
            data.raw = b.read(raw.valid() ? raw : data.reflection, TextureUsage::Sampled);
            data.hiz = b.read(out.hiz, TextureUsage::Sampled);
            data.hit = b.read(out.hit, TextureUsage::Sampled);
            // Only the method debug view reads the weights: otherwise the reflection is bound in
            // their place, so that the graph can cull the half-resolution method upsampling.
            data.debug = b.read(view == DebugView::Method                      ? out.method
                                 : view == DebugView::Cmo && out.cmoInfo.valid() ? out.cmoInfo
                                                                                 : data.reflection,
                                 TextureUsage::Sampled);
            const TextureHandle fresh = separate ? b.create("reflections.lit", litDesc) : historyColor.current;
            data.dst = b.write(variant.tiled ? copiedDst : fresh, TextureUsage::StorageWrite);
            // A debug view replaces the image; the history still gets the real one, or the
            // next frames would reflect the debug colours. With temporal accumulation the
            // history gets this frame's own reflection (composite.comp says why).
            if (separate)
                data.plain = b.write(variant.tiled ? copiedPlain : historyColor.current, TextureUsage::StorageWrite);
        },
        [this, variant, separate](const Data& data, PassContext& pc) {
            const render::Environment& env = renderer.environment();
            gpu::DescriptorWriter w = writer();
            w.sampled("litTex", pc.view(data.lit), nearest)
                .sampled("albedoTex", pc.view(data.albedo), nearest)
                .sampled("normalTex", pc.view(data.normal), nearest)
                .buffer("MaterialTable", materials.get())
                .sampled("emissiveTex", pc.view(data.emissive), nearest)
                .sampled("reflectionTex", pc.view(data.reflection), nearest)
                .sampled("dfgTex", env.dfg().view(), env.sampler())
                .sampled("hiz", pc.view(data.hiz), nearest)
                .sampled("hitTex", pc.view(data.hit), nearest)
                .sampled("debugTex", pc.view(data.debug), nearest)
                .storage("dst", pc.view(data.dst))
                .storage("plainOut", pc.view(separate ? data.plain : data.dst))  // unused when not separate
                .sampled("rawReflectionTex", pc.view(data.raw), nearest)
                .buffer("tiles", pc.buffer(data.tiles));
            // With tiles, the tiles that reflect: those with a screen-space ray and those with
            // lookups only.
            using namespace shader;
            dispatchTiles(pc, w, data.tiles, variant.tiled,
                          {{&composite(variant, kListResolveRay), kListResolveRay},
                           {&composite(variant, kListLookup), kListLookup}},
                          pc.extent(data.dst), data.footprint);
        });
    g.markOutput(separate ? d.plain : d.dst);  // the history: the next frame's reprojection reads it
    return d.dst;
}

Reflections::Impl::HistoryReads Reflections::Impl::readHistory(PassBuilder& b, const ReflectionInputs& in,
                                                               TextureHandle hizPyramid, const HistoryHandles& color,
                                                               const HistoryHandles& normal) const {
    HistoryReads r;
    r.hiz = b.read(hizPyramid, TextureUsage::Sampled);
    r.normal = b.read(in.gbuffer.normal, TextureUsage::Sampled);
    r.emissive = b.read(in.gbuffer.emissive, TextureUsage::Sampled);
    r.motion = b.read(in.gbuffer.motion, TextureUsage::Sampled);
    r.history = b.read(color.previous, TextureUsage::Sampled);
    r.historyNormal = b.read(normal.previous, TextureUsage::Sampled);
    r.historyDepth = b.read(historyHiz.previous, TextureUsage::Sampled, mipLevel(0));
    return r;
}

gpu::DescriptorWriter Reflections::Impl::historyWriter(PassContext& pc, const HistoryReads& r) const {
    gpu::DescriptorWriter w = surfaceWriter(pc, r.hiz, r.normal, r.emissive);
    w.sampled("motionTex", pc.view(r.motion), nearest)
        .sampled("historyTex", pc.view(r.history), nearest)
        .sampled("historyNormal", pc.view(r.historyNormal), nearest)
        .sampled("historyDepth", pc.view(r.historyDepth, mipLevel(0)), nearest);
    return w;
}

TextureHandle Reflections::Impl::addRefresh(FrameGraph& g, const ReflectionInputs& in, TextureHandle hizPyramid,
                                            const ReflectionOutputs& out, TextureHandle half) {
    struct Data {
        HistoryReads reads;
        TextureHandle half, guide, distance, dst, dstNormal;
    };
    historyRefresh = g.importHistory("reflections.history.refresh", history.refresh.history());
    historyRefreshNormal = g.importHistory("reflections.history.refresh_normal", history.refreshNormal.history());
    const auto& d = g.addPass<Data>(
        "reflections.refresh", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.reads = readHistory(b, in, hizPyramid, historyRefresh, historyRefreshNormal);
            data.half = b.read(half, TextureUsage::Sampled);
            data.guide = b.read(out.guide, TextureUsage::Sampled);
            data.distance = b.read(out.distance, TextureUsage::Sampled);
            data.dst = b.write(historyRefresh.current, TextureUsage::StorageWrite);
            data.dstNormal = b.write(historyRefreshNormal.current, TextureUsage::StorageWrite);
        },
        [this](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = historyWriter(pc, data.reads);
            w.sampled("halfTex", pc.view(data.half), nearest)
                .sampled("guideTex", pc.view(data.guide), nearest)
                .sampled("distanceTex", pc.view(data.distance), nearest)
                .storage("refreshedOut", pc.view(data.dst))
                .storage("normalOut", pc.view(data.dstNormal));
            dispatch(pc, refresh, w, pc.extent(data.dst));
        });
    g.markOutput(d.dstNormal);
    return d.dst;
}

TextureHandle Reflections::Impl::addTemporal(FrameGraph& g, const ReflectionInputs& in, TextureHandle hizPyramid,
                                             TextureHandle reflection, TextureHandle distance) {
    struct Data {
        HistoryReads reads;
        TextureHandle reflection, distance, dst, dstNormal;
    };
    historyReflection = g.importHistory("reflections.history.reflection", history.reflection.history());
    historyNormal = g.importHistory("reflections.history.normal", history.normal.history());
    const auto& d = g.addPass<Data>(
        "reflections.temporal", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.reads = readHistory(b, in, hizPyramid, historyReflection, historyNormal);
            data.reflection = b.read(reflection, TextureUsage::Sampled);
            data.distance = b.read(distance, TextureUsage::Sampled);
            data.dst = b.write(historyReflection.current, TextureUsage::StorageWrite);
            data.dstNormal = b.write(historyNormal.current, TextureUsage::StorageWrite);
        },
        [this](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = historyWriter(pc, data.reads);
            w.sampled("reflectionTex", pc.view(data.reflection), nearest)
                .sampled("distanceTex", pc.view(data.distance), nearest)
                .storage("accumulatedOut", pc.view(data.dst))
                .storage("normalOut", pc.view(data.dstNormal));
            dispatch(pc, temporal, w, pc.extent(data.dst));
        });
    g.markOutput(d.dstNormal);
    return d.dst;
}

TextureHandle Reflections::Impl::addHiZView(FrameGraph& g, TextureHandle hizPyramid) {
    struct Data {
        TextureHandle hiz, dst;
    };
    const auto& d = g.addPass<Data>(
        "reflections.hiz_view", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.hiz = b.read(hizPyramid, TextureUsage::Sampled);
            data.dst = b.write(b.create("reflections.hiz_view", TextureDesc{.format = kColorFormat}),
                               TextureUsage::StorageWrite);
        },
        [this](const Data& data, PassContext& pc) {
            gpu::DescriptorWriter w = writer();
            w.sampled("hiz", pc.view(data.hiz), nearest).storage("dst", pc.view(data.dst));
            dispatch(pc, hizView, w, pc.extent(data.dst));
        });
    return d.dst;
}

}  // namespace speculum::reflections
