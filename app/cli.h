// The batch command line: parsing only (no side effects), so every rule is unit-tested.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace caustic {

struct CliOptions {
    std::optional<std::string> scene;        // --scene: batch mode
    std::optional<std::string> editorScene;  // a bare file name: open it in the editor
    std::optional<int> samples, width, height, maxDepth;
    std::optional<std::uint32_t> seed;
    std::string outputDir = "renders";
    bool png = false, hdr = false, exr = false;   // PNG when none is given
    bool reinhard = false;
    float exposure = 0.0f;                   // EV: the image is scaled by 2^exposure before tone mapping
    std::optional<double> timeBudget;        // seconds: render until then instead of a sample count
    std::vector<std::string> sets;           // --set path=value, in order
    std::vector<std::string> sweeps;         // --sweep path=v1,v2,..., in order
    std::string strategy = "mis";            // mis | light | bsdf (for checking MIS)
    bool oidn = false, aovs = false, sky = false;
    std::string oidnGuides = "prefilter";    // --oidn-guides: prefilter | raw | none
    bool half = false;                       // --half: EXR channels as 16-bit half floats
    std::optional<std::string> envmap;
    std::optional<std::string> skyPreset;    // --sky-preset: a named sky look (implies --sky)
    bool help = false, version = false;
};

struct CliParseResult {
    std::optional<CliOptions> options;
    std::string error;   // "--samples: expected an integer >= 1, got '-4'"
};

CliParseResult parseCli(const std::vector<std::string>& args);  // args without argv[0]
std::string cliUsage();

}  // namespace caustic
