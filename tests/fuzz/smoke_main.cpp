// The fixed-run-count smoke of a fuzz harness, for the normal test suite (no libFuzzer, the
// normal compiler): calls the harness's LLVMFuzzerTestOneInput on every seed file, then on a
// number of deterministic mutations of each (a seeded generator; the same runs every time). A
// broken property or a crash aborts, so the ctest test fails; the input is written to
// $CAUSTIC_FUZZ_SMOKE_FAILED (default ./fuzz-smoke-failed-input) first, to replay it.
//
//   caustic_fuzz_smoke_<name> [--mutations N] [--seed S] [--prefix-ext] [--prefix-file F]
//                             [--max-size BYTES] <seed file or folder>...
//
// --prefix-ext: each seed is "<its lowercase extension>\n<its bytes>" (the mesh and image
// harnesses' input) and mutations leave that first line alone. --prefix-file F: F's bytes are put
// in front of each seed (the override lines of fuzz_scene_override). Seeds larger than --max-size
// (default 1 MiB) are skipped and counted. It prints the number of runs.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

// SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators", 2014).
struct Rng {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(next() % n); }
};

// Tokens that break parsers: range edges of float, int and size, JSON structure, numbers that
// are not (the same spirit as libFuzzer's dictionaries).
const char* const kTokens[] = {"1e39", "-1", "nan", "NaN", "inf", "-inf", "1e-45", "3.4028236e38", "null", "true",
                               "0", "4294967296", "-2147483648", "2147483647", "[]", "{}", "\"\"", "[[[[",
                               "\\u0000", "1e308", "-0", "65536", "16385", "\x00\x00\x00\x80", "\xff\xff\xff\xff"};
const std::uint8_t kBytes[] = {0, 0xff, 0x7f, 0x80, 0x01, '0', '9', '-', '.', 'e', '"', '[', ']', '{', '}', ',', ':', '\n', ' '};

void mutate(std::string& s, std::size_t keep, Rng& rng) {
    const int ops = 1 + static_cast<int>(rng.below(4));
    for (int k = 0; k < ops; ++k) {
        const std::size_t n = s.size() > keep ? s.size() - keep : 0;
        auto at = [&] { return keep + rng.below(n); };
        switch (rng.below(n == 0 ? 2 : 9)) {
            case 0: s.insert(keep + rng.below(n + 1), 1, static_cast<char>(rng.next())); break;
            case 1: {
                const char* t = kTokens[rng.below(std::size(kTokens))];
                s.insert(keep + rng.below(n + 1), t, std::max<std::size_t>(std::strlen(t), 1));
                break;
            }
            case 2: {
                const std::size_t i = at();
                s[i] = static_cast<char>(s[i] ^ (1 << rng.below(8)));
                break;
            }
            case 3: s[at()] = static_cast<char>(rng.next()); break;
            case 4: s[at()] = static_cast<char>(kBytes[rng.below(std::size(kBytes))]); break;
            case 5: {
                const std::size_t from = at();
                s.erase(from, 1 + rng.below(16));
                break;
            }
            case 6: {
                const std::size_t from = at();
                const std::string chunk = s.substr(from, 1 + rng.below(64));
                s.insert(keep + rng.below(n + 1), chunk);
                break;
            }
            case 7: s.resize(keep + rng.below(n + 1)); break;
            case 8: {
                const std::size_t from = at();
                const std::uint32_t v = static_cast<std::uint32_t>(rng.next());
                for (std::size_t i = 0; i < 4 && from + i < s.size(); ++i) s[from + i] = static_cast<char>(v >> (8 * i));
                break;
            }
        }
    }
}

std::string readFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const char* gFailedPath = "fuzz-smoke-failed-input";
void run(const std::string& input) {
    // Kept on disk while it runs, so a crash leaves the input that caused it.
    {
        std::ofstream out(gFailedPath, std::ios::binary | std::ios::trunc);
        out.write(input.data(), static_cast<std::streamsize>(input.size()));
    }
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
}

}  // namespace

int main(int argc, char** argv) {
    long mutations = 100;
    std::uint64_t seed = 12;
    bool prefixExt = false;
    std::string prefix;
    std::uintmax_t maxSize = 1 << 20;
    std::vector<std::filesystem::path> seeds;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "%s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--mutations") mutations = std::stol(value());
        else if (a == "--seed") seed = std::stoull(value());
        else if (a == "--prefix-ext") prefixExt = true;
        else if (a == "--prefix-file") prefix = readFile(value());
        else if (a == "--max-size") maxSize = std::stoull(value());
        else if (std::filesystem::is_directory(a)) {
            std::vector<std::filesystem::path> found;
            for (const auto& e : std::filesystem::recursive_directory_iterator(a))
                if (e.is_regular_file()) found.push_back(e.path());
            std::sort(found.begin(), found.end());
            seeds.insert(seeds.end(), found.begin(), found.end());
        } else if (std::filesystem::is_regular_file(a)) {
            seeds.push_back(a);
        } else {
            std::fprintf(stderr, "no such seed file or folder: %s\n", a.c_str());
            return 2;
        }
    }
    if (seeds.empty()) {
        std::fprintf(stderr, "no seeds\n");
        return 2;
    }
    if (const char* f = std::getenv("CAUSTIC_FUZZ_SMOKE_FAILED"); f && *f) gFailedPath = f;
    long runs = 0, skipped = 0;
    for (std::size_t k = 0; k < seeds.size(); ++k) {
        if (std::filesystem::file_size(seeds[k]) > maxSize) {
            ++skipped;
            continue;
        }
        std::string head = prefix;
        if (prefixExt) {
            std::string ext = seeds[k].extension().string();
            if (!ext.empty()) ext.erase(0, 1);
            std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            head += ext + "\n";
        }
        const std::string base = head + readFile(seeds[k]);
        const std::size_t keep = prefixExt ? head.size() : 0;
        run(base);
        ++runs;
        Rng rng{seed * 0x100000001b3ULL + k};
        for (long m = 0; m < mutations; ++m) {
            std::string input = base;
            mutate(input, keep, rng);
            run(input);
            ++runs;
        }
    }
    std::remove(gFailedPath);
    std::printf("%ld runs over %zu seeds (%ld skipped as larger than %ju bytes), no failure\n", runs,
                seeds.size() - static_cast<std::size_t>(skipped), skipped, maxSize);
    return 0;
}
