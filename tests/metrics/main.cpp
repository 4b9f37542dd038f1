// speculum-metrics: the accuracy metrics as a command printing JSON, for the bench and the
// accuracy tests (one implementation: metrics.cpp).
//   speculum-metrics compare --test T.exr --ref R.exr [--ref-mask REFLECTIVE.exr]
//                            [--test-mask REFLECTION.exr] [--scale S] [--heatmap OUT.png]
//                            [--band-image ROUGHNESS.exr --bands 0,0.1,0.3,1.01]
//                            [--ref-error STDERROR.exr]... [--max-ref-error E] [--at-reference-pixels]
//   speculum-metrics flicker --test DIR --ref DIR --aov NAME --frames N [--ref-mask-aov NAME]
//                            [--test-mask-aov NAME] [--scale S] [--ref-error-aov NAME] [--at-reference-pixels]
// Exit 0 done, 2 bad arguments, 3 an image cannot be read or sizes differ.
#include "metrics.hpp"

#include "speculum/app/tool_main.hpp"
#include "speculum/core.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;
using namespace speculum;

namespace {

struct Options {
    std::string test, ref, refMask, testMask, heatmap, aov, refMaskAov, testMaskAov, bandImage, refErrorAov;
    std::vector<float> bands;
    std::vector<std::string> refErrors;
    float scale = 1.0f, maxRefError = metrics::kMaxReferenceError;
    int frames = 0;
    bool atReferencePixels = false;
};

// A test-side image (the engine's frame or its mask) at the reference's size: read whole, or with
// --at-reference-pixels sampled at the reference's pixel centres (metrics::atReferencePixels).
metrics::Image loadTest(const Options& o, const std::string& file, const metrics::Image& ref) {
    metrics::Image img = metrics::load(file);
    return o.atReferencePixels ? metrics::atReferencePixels(img, ref.width, ref.height) : img;
}

std::vector<uint8_t> maskFor(const Options& o, const metrics::Image& size, const std::string& refMask,
                             const std::string& testMask) {
    std::optional<metrics::Image> r, t;
    if (!refMask.empty()) r = metrics::load(refMask);
    if (!testMask.empty()) t = loadTest(o, testMask, size);
    return metrics::reflectiveMask(size.width, size.height, r ? &*r : nullptr, t ? &*t : nullptr);
}

nlohmann::json toJson(const metrics::Scores& s) {
    return {{"pixels", s.pixels},
            {"psnr_db", s.psnr ? nlohmann::json(*s.psnr) : nlohmann::json(nullptr)},
            {"mae", s.mae},
            {"gross_share", s.grossShare}};
}

int compare(const Options& o) {
    metrics::Image ref = metrics::load(o.ref), test = loadTest(o, o.test, ref);
    std::vector<uint8_t> mask = maskFor(o, ref, o.refMask, o.testMask);
    // Pixels where a reference is not converged are not scored, and counted (converged references).
    size_t unconverged = 0;
    for (const std::string& e : o.refErrors) mask = metrics::convergedMask(mask, metrics::load(e), o.maxRefError, unconverged);
    metrics::Scores s = metrics::compare(test, ref, mask, o.scale);
    if (!o.heatmap.empty())
        metrics::writePng(o.heatmap, ref.width, ref.height, metrics::heatmap(test, ref, mask, o.scale));
    nlohmann::json j = toJson(s);
    if (o.atReferencePixels) j["at_reference_pixels"] = true;
    if (!o.refErrors.empty()) j["unconverged_pixels"] = unconverged;
    if (!o.bandImage.empty()) {
        // Per band [edge i, edge i+1) of the band image (the roughness AOV): which method is the
        // more accurate per roughness (issue 13: cone against stochastic glossy).
        if (o.bands.size() < 2) throw argumentError("--bands needs at least two increasing edges");
        metrics::Image band = metrics::load(o.bandImage);
        j["bands"] = nlohmann::json::array();
        for (size_t b = 0; b + 1 < o.bands.size(); ++b) {
            if (!(o.bands[b] < o.bands[b + 1])) throw argumentError("--bands must increase");
            nlohmann::json e = toJson(metrics::compare(test, ref, metrics::bandMask(mask, band, o.bands[b], o.bands[b + 1]), o.scale));
            e["lo"] = o.bands[b];
            e["hi"] = o.bands[b + 1];
            j["bands"].push_back(e);
        }
    }
    std::cout << j.dump() << "\n";
    return 0;
}

std::string frameFile(const std::string& dir, const std::string& aov, int frame) {
    std::ostringstream s;
    s << aov << "." << std::setw(4) << std::setfill('0') << frame << ".exr";
    return (fs::path(dir) / s.str()).string();
}

int flicker(const Options& o) {
    if (o.aov.empty()) throw argumentError("flicker needs --aov NAME");
    if (o.frames < 2) throw argumentError("flicker needs --frames N with N >= 2");
    std::vector<metrics::Image> test, ref;
    std::vector<std::vector<uint8_t>> masks;
    for (int f = 0; f < o.frames; ++f) {
        ref.push_back(metrics::load(frameFile(o.ref, o.aov, f)));
        test.push_back(loadTest(o, frameFile(o.test, o.aov, f), ref.back()));
        masks.push_back(maskFor(o, ref.back(), o.refMaskAov.empty() ? "" : frameFile(o.ref, o.refMaskAov, f),
                                o.testMaskAov.empty() ? "" : frameFile(o.test, o.testMaskAov, f)));
    }
    std::vector<metrics::Image> errors;
    for (int f = 0; f < o.frames && !o.refErrorAov.empty(); ++f)
        errors.push_back(metrics::load(frameFile(o.ref, o.refErrorAov, f)));
    metrics::Flicker e = metrics::excessFlicker(test, ref, masks, errors, o.maxRefError, o.scale);
    nlohmann::json j{{"frames", o.frames}, {"excess_flicker", e.excess}};
    if (!errors.empty()) {
        j["reference_floor"] = e.referenceFloor;
        j["unconverged_pixel_frames"] = e.unconverged;
    }
    if (o.atReferencePixels) j["at_reference_pixels"] = true;
    std::cout << j.dump() << "\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App cli{"speculum-metrics: PSNR, MAE, gross-error share and excess flicker on reflective pixels (JSON)"};
    cli.require_subcommand(1);
    CLI::App* cmp = cli.add_subcommand("compare", "one image against its reference");
    cmp->add_option("--test", o.test, "engine image (EXR)")->required();
    cmp->add_option("--ref", o.ref, "reference image (EXR)")->required();
    cmp->add_option("--ref-mask", o.refMask, "reference 'reflective' AOV: pixels > 0.5 count");
    cmp->add_option("--test-mask", o.testMask, "engine 'reflection' AOV: non-zero pixels count");
    cmp->add_option("--scale", o.scale, "multiplier before clamping to [0, 1] (the scene's exposure)");
    cmp->add_option("--heatmap", o.heatmap, "write an error heatmap PNG");
    cmp->add_option("--band-image", o.bandImage, "image whose first channel splits the scores into bands (roughness AOV)");
    cmp->add_option("--bands", o.bands, "band edges, increasing: [edge i, edge i+1)")->delimiter(',');
    cmp->add_option("--ref-error", o.refErrors,
                    "reference 'stderror' AOV (repeatable): pixels above --max-ref-error are not scored");
    const char* atHelp = "the test is k times the reference's size (k whole): score it at the reference's pixel centres";
    cmp->add_flag("--at-reference-pixels", o.atReferencePixels, atHelp);
    const char* maxErrorHelp = "standard error in display units above which a pixel is left out (default 0.01)";
    cmp->add_option("--max-ref-error", o.maxRefError, maxErrorHelp);
    CLI::App* fl = cli.add_subcommand("flicker", "excess flicker of a frame sequence against its reference");
    fl->add_option("--test", o.test, "engine output folder")->required();
    fl->add_option("--ref", o.ref, "reference output folder")->required();
    fl->add_option("--aov", o.aov, "AOV compared (NAME.FFFF.exr in both)")->required();
    fl->add_option("--frames", o.frames, "frame count")->required();
    fl->add_option("--ref-mask-aov", o.refMaskAov, "reference mask AOV (e.g. reflective)");
    fl->add_option("--test-mask-aov", o.testMaskAov, "engine mask AOV (e.g. reflection)");
    fl->add_option("--scale", o.scale, "multiplier before clamping to [0, 1] (the scene's exposure)");
    fl->add_flag("--at-reference-pixels", o.atReferencePixels, atHelp);
    fl->add_option("--ref-error-aov", o.refErrorAov,
                   "reference 'stderror' AOV (converged path): unconverged pixels left out, the reference's floor reported");
    fl->add_option("--max-ref-error", o.maxRefError, maxErrorHelp);
    return app::toolMain("speculum-metrics", cli, argc, argv, [&] {
        if (!(o.scale > 0.0f)) throw argumentError("--scale must be positive");
        return cmp->parsed() ? compare(o) : flicker(o);
    });
}
