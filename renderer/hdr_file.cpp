#include "renderer/hdr_file.h"

#include "renderer/file_util.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

namespace caustic {

bool readRadianceHdr(const std::string& path, ImageData* out, std::string* error) {
    // Regular files only: a FIFO or /dev/zero would never end.
    if (!checkRegularFile(path, error)) return false;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        *error = path + ": cannot read";
        return false;
    }
    auto fail = [&](const std::string& why) {
        *error = path + ": " + why;
        return false;
    };
    std::string line;
    if (!std::getline(in, line) || line.rfind("#?", 0) != 0) return fail("not a Radiance HDR file (no #? signature)");
    bool rgbe = true;
    while (std::getline(in, line) && !line.empty()) {
        if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe") rgbe = false;
    }
    if (!rgbe) return fail("only the 32-bit_rle_rgbe format is supported");
    if (!std::getline(in, line)) return fail("missing resolution line");
    int w = 0, h = 0;
    char ys[3] = {}, xs[3] = {};
    if (std::sscanf(line.c_str(), "%2s %d %2s %d", ys, &h, xs, &w) != 4 || std::string(ys) != "-Y" ||
        std::string(xs) != "+X" || w <= 0 || h <= 0)
        return fail("unsupported resolution line '" + line + "' (expected -Y <height> +X <width>)");
    // The declared size, before anything is allocated for it.
    if (std::string why = imageSizeProblem(path, w, h, 3); !why.empty()) {
        *error = why;
        return false;
    }
    // The bytes the declared size needs at the least (every row in the densest encoding: flat
    // pixels, 4 bytes each; or run-length, each of the 4 components in runs of at most 127, 2
    // bytes a run), against what the file holds: a few bytes declaring 16384x8192 must not make
    // the reader allocate and clear 1.6 GB before it finds out.
    {
        const std::streamoff here = in.tellg();
        in.seekg(0, std::ios::end);
        const std::streamoff end = in.tellg();
        in.seekg(here);
        const long long flatRow = 4LL * w;
        const long long rleRow = 4 + 4 * 2 * ((w + 126) / 127);
        const long long minRow = w >= 8 && w <= 0x7fff ? std::min(flatRow, rleRow) : flatRow;
        if (here < 0 || end < 0 || !in) return fail("cannot read");
        if (static_cast<long long>(end - here) < minRow * h)
            return fail("truncated: declares " + std::to_string(w) + "x" + std::to_string(h) + " pixels, which need at least " +
                        std::to_string(minRow * h) + " bytes, but the file has " + std::to_string(end - here) +
                        " after the header");
    }
    std::vector<std::uint8_t> scan(static_cast<size_t>(w) * 4);
    out->width = w;
    out->height = h;
    out->channels = 3;
    out->pixels.assign(static_cast<size_t>(w) * h * 3, 0.0f);
    for (int y = 0; y < h; ++y) {
        std::uint8_t head[4];
        if (!in.read(reinterpret_cast<char*>(head), 4)) return fail("truncated at row " + std::to_string(y));
        if (w >= 8 && w <= 0x7fff && head[0] == 2 && head[1] == 2 && ((head[2] << 8) | head[3]) == w) {
            // New run-length encoding: the four components one after another, each in runs.
            for (int c = 0; c < 4; ++c) {
                int x = 0;
                while (x < w) {
                    int count = in.get();
                    if (count == EOF) return fail("truncated at row " + std::to_string(y));
                    if (count > 128) {
                        count -= 128;
                        const int value = in.get();
                        if (value == EOF || x + count > w) return fail("bad run at row " + std::to_string(y));
                        for (int i = 0; i < count; ++i) scan[static_cast<size_t>(x++) * 4 + c] = static_cast<std::uint8_t>(value);
                    } else {
                        if (count == 0 || x + count > w) return fail("bad run at row " + std::to_string(y));
                        for (int i = 0; i < count; ++i) {
                            const int value = in.get();
                            if (value == EOF) return fail("truncated at row " + std::to_string(y));
                            scan[static_cast<size_t>(x++) * 4 + c] = static_cast<std::uint8_t>(value);
                        }
                    }
                }
            }
        } else {
            // Flat pixels (the first one already read).
            std::copy(head, head + 4, scan.begin());
            if (!in.read(reinterpret_cast<char*>(scan.data() + 4), static_cast<std::streamsize>(scan.size() - 4)))
                return fail("truncated at row " + std::to_string(y));
        }
        for (int x = 0; x < w; ++x) {
            const std::uint8_t* p = &scan[static_cast<size_t>(x) * 4];
            float* o = &out->pixels[(static_cast<size_t>(y) * w + x) * 3];
            if (p[3] == 0) continue;
            const float f = std::ldexp(1.0f, int(p[3]) - 136);
            o[0] = float(p[0]) * f;
            o[1] = float(p[1]) * f;
            o[2] = float(p[2]) * f;
        }
    }
    return true;
}

}  // namespace caustic
