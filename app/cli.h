// The batch command line: parsing only (no side effects), so every rule is unit-tested.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace caustic {

// --sample-range A:B: sample indices [begin, end) of every pixel.
struct CliSampleRange {
    std::uint32_t begin = 0, end = 0;
};
// --crop X0:X1,Y0:Y1: pixels [x0, x1) x [y0, y1) of the image (checked against its size later).
struct CliCrop {
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

struct CliOptions {
    // The subcommand, "" for a render: "merge" (inputs: OUT PART...), "compare" (inputs: A B),
    // "sheet" (inputs: LAYOUT.json).
    std::string command;
    std::vector<std::string> inputs;
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
    // Splitting a render into parts (the farm, docs/farm.md).
    std::optional<CliSampleRange> sampleRange;
    std::optional<CliCrop> crop;
    std::optional<int> variant;              // --variant K: only the K-th variant of the sweeps
    bool listVariants = false;               // --list-variants: print the sweep's variants as JSON
    std::optional<int> gpu;                  // --gpu N: the GPU to render on (HeadlessGlContext)
    std::optional<std::string> map;          // compare --map <file.png>: the false-colour error map
};

struct CliParseResult {
    std::optional<CliOptions> options;
    std::string error;   // "--samples: expected an integer >= 1, got '-4'"
};

CliParseResult parseCli(const std::vector<std::string>& args);  // args without argv[0]
// "" when every option given may be used with o.command, else the message for the first one that
// may not ("merge: --samples is not an option of caustic merge").
std::string subcommandProblem(const CliOptions& o, const std::vector<std::string>& args);
std::string cliUsage();

}  // namespace caustic
