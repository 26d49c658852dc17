#include "app/cli.h"

#include "renderer/scene.h"

#include <algorithm>
#include <charconv>
#include <optional>
#include <functional>
#include <map>

namespace caustic {
namespace {

template <class T>
bool parseInt(const std::string& s, long long lo, long long hi, T* out) {
    long long v = 0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || v < lo || v > hi) return false;
    *out = static_cast<T>(v);
    return true;
}

}  // namespace

std::string cliUsage() {
    return R"(usage: caustic --scene <file.json> [options]     render headless and exit
       caustic [scene.json]                         open the editor (needs a display)
       caustic merge <out> <part.exr>...            merge the parts of a split render
       caustic compare <a> <b> [--map <file.png>]   error metrics of image a against reference b
       caustic sheet <layout.json>                  a contact sheet of images (the farm's sweeps)

options:
  --scene <file.json>   the scene to render in batch mode
  --samples <n>         samples per pixel (default: the scene's, else 256)
  --width <px>          image width (default: the scene's, else 800); given alone, the height
                        follows the scene's aspect ratio
  --height <px>         image height (default: the scene's, else 600); given alone, the width
                        follows
  --max-depth <n>       maximum scattering events per path (default: the scene's, else 10)
  --seed <n>            random seed, 0..4294967295 (default: the scene's, else 0)
  --output <dir>        output folder, created if missing (default: renders); files are named
                        after the scene
  --png | --hdr | --exr output formats, any combination (default: --png); PNG is 8-bit sRGB
                        after tone mapping, HDR (Radiance) and EXR are linear float
  --half                EXR channels as 16-bit half floats (default: 32-bit float)
  --reinhard            Reinhard tone mapping for PNG (default: ACES filmic)
  --exposure <ev>       scale the image by 2^ev before tone mapping (PNG only; default 0)
  --time <seconds>      render until the time is up instead of a sample count
  --set <path>=<value>  override a value of the scene for this run, e.g. --set camera.fov=30,
                        --set 'materials[white].albedo=[1,1,1]' (repeatable; JSON value, else text)
  --sweep <path>=<v1>,<v2>,...
                        render one image per value (repeatable: the sweeps form a grid) and a
                        contact sheet <scene>-sheet.png with a labelled cell per variant
  --strategy <s>        mis (default), light or bsdf: direct lighting by multiple importance
                        sampling, or by one strategy alone (all three converge to the same image)
  --sky                 replace the scene's environment with the procedural sky (its default
                        look: a white horizon to a blue zenith, a key light)
  --sky-preset <name>   the same with a named look: default, or original (a dark teal horizon
                        to a white zenith, scaled down to fill light); see docs/scene-format.md
  --envmap <file.hdr>   light the scene with an equirectangular HDR environment map (wins
                        over --sky and the scene's own environment)
  --oidn                denoise with Intel Open Image Denoise (filter RT, HDR, albedo and normal
                        as guides); the written images are the denoised ones
  --oidn-guides <g>     prefilter (default: the guides are denoised first, OIDN's best quality),
                        raw (guides as rendered) or none (colour alone)
  --aovs                also write the albedo and normal passes: <scene>-albedo and <scene>-normal
                        for PNG/HDR (normal remapped from [-1, 1] to [0, 1]); with --exr one
                        multi-layer EXR with layers raw, denoised (with --oidn), albedo, normal
  --sample-range <a:b>  render only sample indices [a, b) of every pixel, into a part file
  --crop <x0:x1,y0:y1>  render only pixels [x0, x1) x [y0, y1), into a part file; with either
                        flag caustic writes <scene>.part-s<a>-<b>-x<x0>-<x1>-y<y0>-<y1>.exr
                        (the sums, counts and AOVs; docs/farm.md) and no image: caustic merge
                        combines parts into the image a single render would have made
  --variant <k>         with --sweep: render only variant k (0-based, the order of the sheet)
  --list-variants       print each variant of the sweeps (or the one render) as a JSON line:
                        index, label, suffix, width, height, samples, seed, columns; and exit
  --gpu <n>             render on GPU n (its CUDA number where the driver tells it); the default
                        is the first GPU, else software rendering
  --help                show this text
  --version             show the version

merge: <out> names the output without extension (its formats come from --png/--hdr/--exr,
  default PNG) or with one (.png, .hdr or .exr: that format). Options: --png --hdr --exr --half
  --reinhard --exposure --oidn --oidn-guides --aovs. Parts must come from one scene, seed and
  image size, and no two may hold the same sample of a pixel.
compare: prints relMSE, RMSE and the largest differences of <a> against <b> as one JSON object;
  --map writes a false-colour map of the per-pixel relative error.

Written files are printed on stdout, one per line; progress and the summary go to stderr.
Exit status: 0 success, 1 the render failed (bad scene, GL or I/O error), 2 bad command line.
)";
}

CliParseResult parseCli(const std::vector<std::string>& args) {
    CliOptions o;
    CliParseResult result;
    using Handler = std::function<bool(const std::string&, std::string*)>;
    auto intFlag = [](auto* field, long long lo, long long hi) {
        return [=](const std::string& v, std::string* why) {
            using T = typename std::decay_t<decltype(*field)>::value_type;
            T parsed{};
            if (!parseInt(v, lo, hi, &parsed)) {
                *why = "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + v + "'";
                return false;
            }
            *field = parsed;
            return true;
        };
    };
    const std::map<std::string, Handler> withValue = {
        {"--scene", [&](const std::string& v, std::string* why) {
             if (v.empty()) { *why = "expected a scene file, got ''"; return false; }
             o.scene = v;
             return true;
         }},
        {"--samples", intFlag(&o.samples, 1, 1 << 24)},
        {"--width", intFlag(&o.width, 1, kMaxRenderSide)},
        {"--height", intFlag(&o.height, 1, kMaxRenderSide)},
        {"--max-depth", intFlag(&o.maxDepth, 0, 1024)},
        {"--seed", intFlag(&o.seed, 0, 4294967295LL)},
        {"--output", [&](const std::string& v, std::string* why) {
             if (v.empty()) { *why = "expected a folder"; return false; }
             o.outputDir = v;
             return true;
         }},
        {"--strategy", [&](const std::string& v, std::string* why) {
             if (v != "mis" && v != "light" && v != "bsdf") { *why = "expected mis, light or bsdf, got '" + v + "'"; return false; }
             o.strategy = v;
             return true;
         }},
        {"--exposure", [&](const std::string& v, std::string* why) {
             float x = 0;
             auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
             if (ec != std::errc() || ptr != v.data() + v.size() || !(x > -64.0f && x < 64.0f)) {
                 *why = "expected a number of stops in (-64, 64), got '" + v + "'";
                 return false;
             }
             o.exposure = x;
             return true;
         }},
        {"--time", [&](const std::string& v, std::string* why) {
             double x = 0;
             auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
             if (ec != std::errc() || ptr != v.data() + v.size() || !(x > 0.0 && x <= 1e6)) {
                 *why = "expected seconds in (0, 1e6], got '" + v + "'";
                 return false;
             }
             o.timeBudget = x;
             return true;
         }},
        {"--set", [&](const std::string& v, std::string* why) {
             if (v.find('=') == std::string::npos || v.front() == '=') { *why = "expected <json.path>=<value>, got '" + v + "'"; return false; }
             o.sets.push_back(v);
             return true;
         }},
        {"--sweep", [&](const std::string& v, std::string* why) {
             if (v.find('=') == std::string::npos || v.front() == '=') { *why = "expected <json.path>=<v1>,<v2>,..., got '" + v + "'"; return false; }
             o.sweeps.push_back(v);
             return true;
         }},
        {"--envmap", [&](const std::string& v, std::string* why) {
             if (v.empty()) { *why = "expected an image file, got ''"; return false; }
             o.envmap = v;
             return true;
         }},
        {"--sky-preset", [&](const std::string& v, std::string* why) {
             if (!findSkyPreset(v)) {
                 std::string names;
                 for (const SkyPreset& p : skyPresets()) names += (names.empty() ? "" : ", ") + std::string(p.name);
                 *why = "expected " + names + ", got '" + v + "'";
                 return false;
             }
             o.skyPreset = v;
             o.sky = true;
             return true;
         }},
        {"--sample-range", [&](const std::string& v, std::string* why) {
             CliSampleRange r;
             const auto colon = v.find(':');
             if (colon == std::string::npos || !parseInt(v.substr(0, colon), 0, 1 << 24, &r.begin) ||
                 !parseInt(v.substr(colon + 1), 1, 1 << 24, &r.end) || r.begin >= r.end) {
                 *why = "expected <a>:<b> with 0 <= a < b <= 16777216, got '" + v + "'";
                 return false;
             }
             o.sampleRange = r;
             return true;
         }},
        {"--crop", [&](const std::string& v, std::string* why) {
             CliCrop c;
             const auto comma = v.find(',');
             auto pair = [](const std::string& t, int* a, int* b) {
                 const auto colon = t.find(':');
                 return colon != std::string::npos && parseInt(t.substr(0, colon), 0, kMaxRenderSide, a) &&
                        parseInt(t.substr(colon + 1), 1, kMaxRenderSide, b) && *a < *b;
             };
             if (comma == std::string::npos || !pair(v.substr(0, comma), &c.x0, &c.x1) ||
                 !pair(v.substr(comma + 1), &c.y0, &c.y1)) {
                 *why = "expected <x0>:<x1>,<y0>:<y1> with x0 < x1 and y0 < y1 (pixels, end excluded), got '" + v + "'";
                 return false;
             }
             o.crop = c;
             return true;
         }},
        {"--variant", intFlag(&o.variant, 0, 1 << 20)},
        {"--gpu", intFlag(&o.gpu, 0, 1023)},
        {"--map", [&](const std::string& v, std::string* why) {
             if (v.empty()) { *why = "expected an image file"; return false; }
             o.map = v;
             return true;
         }},
        {"--oidn-guides", [&](const std::string& v, std::string* why) {
             if (v != "prefilter" && v != "raw" && v != "none") { *why = "expected prefilter, raw or none, got '" + v + "'"; return false; }
             o.oidnGuides = v;
             return true;
         }},
    };
    const std::map<std::string, bool*> switches = {
        {"--png", &o.png}, {"--hdr", &o.hdr}, {"--exr", &o.exr}, {"--reinhard", &o.reinhard},
        {"--oidn", &o.oidn}, {"--aovs", &o.aovs}, {"--sky", &o.sky}, {"--help", &o.help},
        {"--version", &o.version}, {"--half", &o.half}, {"--list-variants", &o.listVariants},
    };
    size_t first = 0;
    if (!args.empty() && (args[0] == "merge" || args[0] == "compare" || args[0] == "sheet")) {
        o.command = args[0];
        first = 1;
    }
    for (size_t i = first; i < args.size(); ++i) {
        std::string arg = args[i];
        std::string value;
        bool hasInlineValue = false;
        if (auto eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
            value = arg.substr(eq + 1);
            arg = arg.substr(0, eq);
            hasInlineValue = true;
        }
        if (auto it = switches.find(arg); it != switches.end()) {
            if (hasInlineValue) { result.error = arg + ": takes no value"; return result; }
            *it->second = true;
        } else if (auto wv = withValue.find(arg); wv != withValue.end()) {
            if (!hasInlineValue) {
                if (i + 1 >= args.size()) { result.error = arg + ": missing value"; return result; }
                value = args[++i];
            }
            std::string why;
            if (!wv->second(value, &why)) { result.error = arg + ": " + why; return result; }
        } else if (arg.rfind("-", 0) == 0 && arg.size() > 1) {
            result.error = arg + ": unknown option (see --help)";
            return result;
        } else if (!o.command.empty()) {
            o.inputs.push_back(arg);
        } else if (!o.editorScene) {
            o.editorScene = arg;  // `caustic scene.json`: the scene to open in the editor
        } else {
            result.error = "unexpected argument '" + arg + "'";
            return result;
        }
    }
    if (!o.command.empty() && !o.help) {
        if (std::string why = subcommandProblem(o, args); !why.empty()) {
            result.error = why;
            return result;
        }
    }
    result.options = o;
    return result;
}

std::string subcommandProblem(const CliOptions& o, const std::vector<std::string>& args) {
    static const std::map<std::string, std::vector<std::string>> allowed = {
        {"merge", {"--png", "--hdr", "--exr", "--half", "--reinhard", "--exposure", "--oidn", "--oidn-guides", "--aovs"}},
        {"compare", {"--map"}},
        {"sheet", {}},
    };
    const auto it = allowed.find(o.command);
    if (it == allowed.end()) return "";
    for (const std::string& a : args) {
        if (a.rfind("--", 0) != 0) continue;
        const std::string flag = a.substr(0, a.find('='));
        if (flag == "--help") continue;
        if (std::find(it->second.begin(), it->second.end(), flag) == it->second.end())
            return o.command + ": " + flag + " is not an option of caustic " + o.command + " (see --help)";
    }
    const size_t need = o.command == "merge" ? 2 : o.command == "compare" ? 2 : 1;
    if (o.inputs.size() < need || (o.command != "merge" && o.inputs.size() > need))
        return o.command == "merge"     ? "merge: expected <out> <part.exr>..., got " + std::to_string(o.inputs.size()) + " arguments"
               : o.command == "compare" ? "compare: expected <image> <reference>, got " + std::to_string(o.inputs.size()) + " arguments"
                                        : "sheet: expected <layout.json>, got " + std::to_string(o.inputs.size()) + " arguments";
    return "";
}

}  // namespace caustic
