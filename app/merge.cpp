// caustic merge OUT PART...: the parts of a split render combined into the image one render
// would have made (docs/farm.md): the parts are checked against each other (one render, every
// pixel's samples held exactly once and the same for every pixel), their sums added (in double,
// in the order of their sample ranges), then resolved, tone mapped, denoised and written as a
// render's would be.
#include "app/commands.h"
#include "app/outputs.h"
#include "app/part_file.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <new>
#include <set>

namespace fs = std::filesystem;

namespace caustic {
namespace {

// The memory free for a new allocation (MemAvailable in /proc/meminfo), or 0 when it is unknown.
double availableMemoryBytes() {
    std::ifstream in("/proc/meminfo");
    std::string key, unit;
    double value = 0.0;
    while (in >> key >> value >> unit)
        if (key == "MemAvailable:") return value * 1024.0;
    return 0.0;
}

}  // namespace

int commandFailed(const std::string& message, int code) {
    std::cerr << "caustic: error: " << message << "\n";
    return code;
}

namespace {

std::string rectText(int x0, int x1, int y0, int y1) {
    return std::to_string(x0) + ":" + std::to_string(x1) + "," + std::to_string(y0) + ":" + std::to_string(y1);
}

std::string rangeText(std::uint32_t a, std::uint32_t b) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "[%u, %u)", a, b);
    return buf;
}

}  // namespace

int runMerge(const CliOptions& given) {
    CliOptions o = given;
    std::string out = o.inputs[0];
    const std::vector<std::string> paths(o.inputs.begin() + 1, o.inputs.end());
    // OUT with an image extension names that file (and its format); without one it is the stem.
    const std::string ext = fs::path(out).extension().string();
    if (ext == ".png" || ext == ".hdr" || ext == ".exr") {
        (ext == ".png" ? o.png : ext == ".hdr" ? o.hdr : o.exr) = true;
        out = out.substr(0, out.size() - ext.size());
    }
    if (std::string why = outputsNotAvailable(o); !why.empty()) return commandFailed(why);
    if (std::set<std::string>(paths.begin(), paths.end()).size() != paths.size())
        return commandFailed("merge: a part file is named twice", kExitBadUsage);

    // Every part's header is read and checked (format, metadata, size) before anything merges;
    // the pixels (and their checksums) are read one part at a time below, so a merge holds one
    // part and the merged sums in memory, however many parts there are.
    std::vector<Part> parts(paths.size());
    std::string error;
    for (size_t i = 0; i < paths.size(); ++i)
        if (!readPart(paths[i], &parts[i], &error, false)) return commandFailed(error);

    // One render: the same image size, seed and render identity (scene, settings, version).
    const PartInfo& first = parts[0].info;
    for (size_t i = 1; i < parts.size(); ++i) {
        const PartInfo& p = parts[i].info;
        const std::string both = paths[i] + " and " + paths[0];
        if (p.width != first.width || p.height != first.height)
            return commandFailed("merge: " + both + " are parts of images of different sizes (" + std::to_string(p.width) +
                                 "x" + std::to_string(p.height) + " and " + std::to_string(first.width) + "x" +
                                 std::to_string(first.height) + ")");
        if (p.seed != first.seed)
            return commandFailed("merge: " + both + " were rendered with different seeds (" + std::to_string(p.seed) + " and " +
                                 std::to_string(first.seed) + ")");
        if (p.renderHash != first.renderHash)
            return commandFailed("merge: " + both + " are parts of different renders: different scenes or settings (" +
                                 p.scene + (p.variant.empty() ? "" : " [" + p.variant + "]") + ", " + first.scene +
                                 (first.variant.empty() ? "" : " [" + first.variant + "]") + "; render hash " +
                                 p.renderHash + " and " + first.renderHash +
                                 (p.version != first.version ? "; caustic " + p.version + " and " + first.version : "") + ")");
    }

    // The image cut along every crop edge: within a cell the same parts hold every pixel. In
    // each cell the parts' sample ranges must not overlap and must join into one range, the same
    // range in every cell (the image a single render of those samples would make).
    std::vector<int> xs = {0, first.width}, ys = {0, first.height};
    for (const Part& p : parts) {
        xs.push_back(p.info.crop.x0), xs.push_back(p.info.crop.x1);
        ys.push_back(p.info.crop.y0), ys.push_back(p.info.crop.y1);
    }
    for (auto* v : {&xs, &ys}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    std::uint32_t lo = 0, hi = 0;
    std::string firstCell;
    for (size_t yi = 0; yi + 1 < ys.size(); ++yi)
        for (size_t xi = 0; xi + 1 < xs.size(); ++xi) {
            const int x0 = xs[xi], x1 = xs[xi + 1], y0 = ys[yi], y1 = ys[yi + 1];
            const std::string cell = rectText(x0, x1, y0, y1);
            std::vector<size_t> holders;
            for (size_t i = 0; i < parts.size(); ++i) {
                const PixelRect& c = parts[i].info.crop;
                if (c.x0 <= x0 && x1 <= c.x1 && c.y0 <= y0 && y1 <= c.y1) holders.push_back(i);
            }
            if (holders.empty()) return commandFailed("merge: no part holds pixels " + cell + " of the " + std::to_string(first.width) + "x" + std::to_string(first.height) + " image");
            std::sort(holders.begin(), holders.end(),
                      [&](size_t a, size_t b) { return parts[a].info.sample0 < parts[b].info.sample0; });
            for (size_t k = 1; k < holders.size(); ++k) {
                const PartInfo& a = parts[holders[k - 1]].info;
                const PartInfo& b = parts[holders[k]].info;
                if (b.sample0 < a.sample1)
                    return commandFailed("merge: " + paths[holders[k - 1]] + " and " + paths[holders[k]] +
                                         " overlap: both hold samples " + rangeText(b.sample0, std::min(a.sample1, b.sample1)) +
                                         " of pixels " + cell);
                if (b.sample0 > a.sample1)
                    return commandFailed("merge: no part holds samples " + rangeText(a.sample1, b.sample0) + " of pixels " +
                                         cell + " (between " + paths[holders[k - 1]] + " and " + paths[holders[k]] + ")");
            }
            const std::uint32_t cellLo = parts[holders.front()].info.sample0, cellHi = parts[holders.back()].info.sample1;
            if (firstCell.empty()) {
                lo = cellLo, hi = cellHi, firstCell = cell;
            } else if (cellLo != lo || cellHi != hi) {
                return commandFailed("merge: pixels " + cell + " have samples " + rangeText(cellLo, cellHi) + " but pixels " +
                                     firstCell + " have " + rangeText(lo, hi) + ": every pixel needs the same samples");
            }
        }

    // The sums, in double, added part by part in the order of the sample ranges (so a pixel's
    // parts are added in that order); a pixel held by one part keeps its floats exactly (a crop
    // merges bit for bit). Each part's pixels are read and checked (checksum) only here.
    const size_t w = size_t(first.width), n = w * size_t(first.height);
    // The memory the merge needs, from the headers, against what the machine has free: the sums
    // in double (4 x 32 bytes a pixel) and, for the largest part, its pixels read as floats twice
    // (the file's 15 channels and the sums made of them).
    {
        std::size_t largest = 0, largestPart = 0;
        for (size_t k = 0; k < parts.size(); ++k) {
            const PixelRect& c = parts[k].info.crop;
            const std::size_t px = std::size_t(c.x1 - c.x0) * std::size_t(c.y1 - c.y0);
            if (px > largest) largest = px, largestPart = k;
        }
        const double need = double(n) * 4 * sizeof(glm::dvec4) + double(largest) * 2 * 15 * sizeof(float);
        const double free = availableMemoryBytes();
        if (free > 0 && need > free)
            return commandFailed("merge: the " + std::to_string(first.width) + "x" + std::to_string(first.height) +
                                 " image (as " + paths[0] + " declares) and its largest part " + paths[largestPart] +
                                 " need " + std::to_string(static_cast<long long>(need / (1 << 20))) + " MiB; " +
                                 std::to_string(static_cast<long long>(free / (1 << 20))) + " MiB are free");
    }
    std::vector<glm::dvec4> sum, sumSq, albedo, normal;
    try {
        sum.assign(n, glm::dvec4(0.0));
        sumSq.assign(n, glm::dvec4(0.0));
        albedo.assign(n, glm::dvec4(0.0));
        normal.assign(n, glm::dvec4(0.0));
    } catch (const std::bad_alloc&) {
        return commandFailed("merge: the " + std::to_string(first.width) + "x" + std::to_string(first.height) +
                             " image's sums need " + std::to_string(n * 4 * sizeof(glm::dvec4) >> 20) +
                             " MiB, more memory than there is (" + paths[0] + " declares that size)");
    }
    std::vector<size_t> order(parts.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return parts[a].info.sample0 < parts[b].info.sample0; });
    for (size_t k : order) {
        Part p;
        if (!readPart(paths[k], &p, &error)) return commandFailed(error);
        const PixelRect& c = p.info.crop;
        for (int y = c.y0; y < c.y1; ++y)
            for (int x = c.x0; x < c.x1; ++x) {
                const size_t j = size_t(y - c.y0) * size_t(p.sums.width) + size_t(x - c.x0), i = size_t(y) * w + size_t(x);
                sum[i] += glm::dvec4(p.sums.sum[j]);
                sumSq[i] += glm::dvec4(p.sums.sumSq[j]);
                albedo[i] += glm::dvec4(p.sums.albedo[j]);
                normal[i] += glm::dvec4(p.sums.normal[j]);
            }
    }
    Accumulators merged;
    merged.width = first.width;
    merged.height = first.height;
    merged.sum.assign(sum.begin(), sum.end());
    merged.sumSq.assign(sumSq.begin(), sumSq.end());
    merged.albedo.assign(albedo.begin(), albedo.end());
    merged.normal.assign(normal.begin(), normal.end());
    sum = sumSq = albedo = normal = {};

    // The output's folder, as a render checks its --output.
    const fs::path folder = fs::path(out).parent_path();
    std::error_code ec;
    if (!folder.empty()) fs::create_directories(folder, ec);
    if (!folder.empty() && (ec || !fs::is_directory(folder)))
        return commandFailed("merge: " + folder.string() + ": cannot create folder: " + ec.message());
    if (access(folder.empty() ? "." : folder.c_str(), W_OK) != 0)
        return commandFailed("merge: " + (folder.empty() ? std::string(".") : folder.string()) + ": folder is not writable");

    double seconds = 0.0;
    std::uint64_t dropped = 0;
    for (const Part& p : parts) seconds += p.info.seconds, dropped += p.info.dropped;
    ImageMetadata meta = {
        {"Software", std::string("caustic ") + CAUSTIC_VERSION},
        {"caustic:scene", first.scene},
        {"caustic:samples", std::to_string(hi - lo)},
        {"caustic:seed", std::to_string(first.seed)},
        {"caustic:render_seconds", std::to_string(seconds)},
        {"caustic:merged_parts", std::to_string(parts.size())},
        {"caustic:sample_range", std::to_string(lo) + ":" + std::to_string(hi)},
    };
    if (!first.variant.empty()) meta.push_back({"caustic:variant", first.variant});
    const Film film = resolveFilm(merged);
    if (!writeOutputs(o, out, film, meta, nullptr, &error)) return commandFailed(error);
    std::fprintf(stderr, "caustic: merged %zu parts of %s: %dx%d, samples [%u, %u) (%u spp), %.2f s of rendering; %llu NaN/Inf samples dropped\n",
                 parts.size(), first.scene.c_str(), first.width, first.height, lo, hi, hi - lo, seconds,
                 static_cast<unsigned long long>(dropped));
    return 0;
}

}  // namespace caustic
