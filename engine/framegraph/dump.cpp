// Graphviz and JSON views of the graph for debugging and the editor.
#include "framegraph/compile_stages.hpp"

#include <nlohmann/json.hpp>

#include <sstream>

namespace speculum {
namespace {

std::string dotEscape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out;
}

std::string rangeLabel(const Subresource& r, const TextureDesc& d) {
    if (r.baseMip == 0 && r.mipCount == d.mips && r.baseLayer == 0 && r.layerCount == d.layers) {
        return "";
    }
    std::string s = " mip " + std::to_string(r.baseMip);
    if (r.mipCount > 1) s += ".." + std::to_string(r.baseMip + r.mipCount - 1);
    if (r.baseLayer != 0 || r.layerCount != d.layers) {
        s += " layer " + std::to_string(r.baseLayer);
        if (r.layerCount > 1) s += ".." + std::to_string(r.baseLayer + r.layerCount - 1);
    }
    return s;
}

nlohmann::json rangeJson(const Subresource& r) {
    return {{"baseMip", r.baseMip}, {"mipCount", r.mipCount}, {"baseLayer", r.baseLayer},
            {"layerCount", r.layerCount}};
}

nlohmann::json barrierJson(const TextureBarrier& b, const FrameGraph::Impl& g) {
    return {{"texture", b.texture}, {"name", textureName(g, b.texture)},
            {"range", rangeJson(b.range)}, {"srcStage", b.srcStage}, {"srcAccess", b.srcAccess},
            {"dstStage", b.dstStage}, {"dstAccess", b.dstAccess},
            {"oldLayout", layoutName(b.oldLayout)}, {"newLayout", layoutName(b.newLayout)}};
}

nlohmann::json passJson(const FrameGraph::Impl& g, uint32_t p, int order) {
    const PassNode& pass = g.passes[p];
    static const char* kTypes[] = {"Raster", "Compute", "Transfer"};
    nlohmann::json j = {{"name", pass.name}, {"index", p}, {"type", kTypes[int(pass.type)]},
                        {"order", order}, {"culled", order < 0},
                        {"sideEffect", pass.sideEffect}};
    j["reads"] = nlohmann::json::array();
    j["writes"] = nlohmann::json::array();
    for (const TextureAccess& a : pass.textures) {
        j[a.write ? "writes" : "reads"].push_back(
            {{"texture", a.texture}, {"name", textureName(g, a.texture)},
             {"version", a.version}, {"usage", usageName(a.usage)},
             {"range", rangeJson(a.range)}});
    }
    for (const BufferAccess& a : pass.buffers) {
        j[a.write ? "writes" : "reads"].push_back({{"buffer", a.buffer},
                                                   {"name", g.buffers[a.buffer].name},
                                                   {"version", a.version},
                                                   {"usage", usageName(a.usage)}});
    }
    j["textureBarriers"] = nlohmann::json::array();
    j["bufferBarriers"] = nlohmann::json::array();
    if (order >= 0) {
        const CompiledPass& cp = g.compiled.passes[order];
        for (const TextureBarrier& b : cp.textureBarriers) {
            j["textureBarriers"].push_back(barrierJson(b, g));
        }
        for (const BufferBarrier& b : cp.bufferBarriers) {
            j["bufferBarriers"].push_back({{"buffer", b.buffer}, {"srcStage", b.srcStage},
                                           {"srcAccess", b.srcAccess}, {"dstStage", b.dstStage},
                                           {"dstAccess", b.dstAccess}});
        }
    }
    return j;
}

nlohmann::json placementJson(const CompiledGraph& c, bool isTexture, uint32_t id) {
    for (const Placement& p : c.placements) {
        if (p.isTexture == isTexture && p.resource == id) {
            return {{"offset", p.offset}, {"size", p.size}};
        }
    }
    return nullptr;
}

nlohmann::json lifetimeJson(const std::vector<Lifetime>& lifetimes, uint32_t id) {
    if (id >= lifetimes.size() || !isUsed(lifetimes[id])) return nullptr;
    return {{"first", lifetimes[id].first}, {"last", lifetimes[id].last}};
}

// Execution position of every declared pass, -1 when culled (or not compiled).
std::vector<int> executionOrder(const FrameGraph::Impl& g) {
    std::vector<int> order(g.passes.size(), -1);
    if (!g.isCompiled) return order;
    for (size_t i = 0; i < g.compiled.passes.size(); ++i) order[g.compiled.passes[i].pass] = int(i);
    return order;
}

}  // namespace

std::string FrameGraph::dumpDot() const {
    const Impl& g = *impl_;
    std::vector<int> order = executionOrder(g);
    std::ostringstream out;
    out << "digraph framegraph {\n  rankdir=LR;\n";
    for (uint32_t p = 0; p < g.passes.size(); ++p) {
        bool culled = g.isCompiled && order[p] < 0;
        out << "  p" << p << " [shape=box, label=\"" << dotEscape(g.passes[p].name);
        if (order[p] >= 0) out << "\\n#" << order[p];
        out << "\"" << (culled ? ", style=filled, fillcolor=lightgrey, fontcolor=grey40" : "")
            << "];\n";
    }
    for (uint32_t t = 0; t < g.textures.size(); ++t) {
        const TextureDesc& d = g.textures[t].info.desc;
        out << "  t" << t << " [shape=ellipse, label=\"" << dotEscape(g.textures[t].info.name)
            << "\\n" << d.width << "x" << d.height << "\""
            << (g.textures[t].imported ? ", peripheries=2" : "") << "];\n";
    }
    for (uint32_t b = 0; b < g.buffers.size(); ++b) {
        out << "  b" << b << " [shape=ellipse, label=\"" << dotEscape(g.buffers[b].name) << "\""
            << (g.buffers[b].imported ? ", peripheries=2" : "") << "];\n";
    }
    for (uint32_t p = 0; p < g.passes.size(); ++p) {
        for (const TextureAccess& a : g.passes[p].textures) {
            std::string label = std::string(usageName(a.usage)) +
                                rangeLabel(a.range, g.textures[a.texture].info.desc);
            if (a.write) out << "  p" << p << " -> t" << a.texture;
            else out << "  t" << a.texture << " -> p" << p;
            out << " [label=\"" << label << "\"" << (a.write ? ", color=red" : "") << "];\n";
        }
        for (const BufferAccess& a : g.passes[p].buffers) {
            if (a.write) out << "  p" << p << " -> b" << a.buffer;
            else out << "  b" << a.buffer << " -> p" << p;
            out << " [label=\"" << usageName(a.usage) << "\"" << (a.write ? ", color=red" : "")
                << "];\n";
        }
    }
    out << "}\n";
    return out.str();
}

nlohmann::json FrameGraph::dumpJson() const {
    const Impl& g = *impl_;
    std::vector<int> order = executionOrder(g);
    nlohmann::json j;
    j["compiled"] = g.isCompiled;
    j["output"] = {{"width", g.config.outputWidth}, {"height", g.config.outputHeight}};
    j["passes"] = nlohmann::json::array();
    for (uint32_t p = 0; p < g.passes.size(); ++p) j["passes"].push_back(passJson(g, p, order[p]));
    j["textures"] = nlohmann::json::array();
    for (uint32_t t = 0; t < g.textures.size(); ++t) {
        const TextureInfo& info = g.textures[t].info;
        j["textures"].push_back(
            {{"id", t}, {"name", info.name}, {"width", info.desc.width},
             {"height", info.desc.height}, {"format", int(info.desc.format)},
             {"mips", info.desc.mips}, {"layers", info.desc.layers}, {"cube", info.desc.cube},
             {"usage", info.usage}, {"imported", info.imported},
             {"lifetime", lifetimeJson(g.compiled.textureLifetimes, t)},
             {"placement", placementJson(g.compiled, true, t)}});
    }
    j["buffers"] = nlohmann::json::array();
    for (uint32_t b = 0; b < g.buffers.size(); ++b) {
        const BufferNode& buf = g.buffers[b];
        j["buffers"].push_back({{"id", b}, {"name", buf.name}, {"size", buf.desc.size},
                                {"usage", buf.usage}, {"imported", buf.imported.has_value()},
                                {"lifetime", lifetimeJson(g.compiled.bufferLifetimes, b)},
                                {"placement", placementJson(g.compiled, false, b)}});
    }
    j["finalBarriers"] = nlohmann::json::array();
    for (const TextureBarrier& b : g.compiled.finalTextureBarriers) {
        j["finalBarriers"].push_back(barrierJson(b, g));
    }
    j["memory"] = {{"transientWithAliasing", g.compiled.memory.transientWithAliasing},
                   {"transientWithoutAliasing", g.compiled.memory.transientWithoutAliasing}};
    return j;
}

}  // namespace speculum
