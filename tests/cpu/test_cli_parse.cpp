// The batch command-line parser (app/cli.cpp): defaults, every flag in both spellings, and the
// wording of every kind of error (each names the flag or the argument at fault).
#include "app/cli.h"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace caustic;

namespace {

CliOptions parseOk(const std::vector<std::string>& args) {
    CliParseResult r = parseCli(args);
    INFO("error: " << r.error);
    REQUIRE(r.options.has_value());
    CHECK(r.error.empty());
    return *r.options;
}

std::string parseError(const std::vector<std::string>& args) {
    CliParseResult r = parseCli(args);
    CHECK_FALSE(r.options.has_value());
    CHECK_FALSE(r.error.empty());
    return r.error;
}

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

}  // namespace

TEST_CASE("parseCli: no arguments gives the defaults", "[cli]") {
    const CliOptions o = parseOk({});
    CHECK_FALSE(o.scene);
    CHECK_FALSE(o.editorScene);
    CHECK_FALSE(o.samples);
    CHECK_FALSE(o.width);
    CHECK_FALSE(o.height);
    CHECK_FALSE(o.maxDepth);
    CHECK_FALSE(o.seed);
    CHECK(o.outputDir == "renders");
    CHECK_FALSE(o.png);
    CHECK_FALSE(o.hdr);
    CHECK_FALSE(o.exr);
    CHECK_FALSE(o.reinhard);
    CHECK_FALSE(o.oidn);
    CHECK_FALSE(o.aovs);
    CHECK_FALSE(o.sky);
    CHECK_FALSE(o.envmap);
    CHECK_FALSE(o.help);
    CHECK_FALSE(o.version);
}

TEST_CASE("parseCli: every flag with a separate value", "[cli]") {
    const CliOptions o = parseOk({"--scene", "scenes/a.json", "--samples", "64", "--width", "320",
                                  "--height", "200", "--max-depth", "5", "--seed", "42", "--output",
                                  "out/dir", "--envmap", "sky.hdr"});
    REQUIRE(o.scene);
    CHECK(*o.scene == "scenes/a.json");
    CHECK(o.samples == 64);
    CHECK(o.width == 320);
    CHECK(o.height == 200);
    CHECK(o.maxDepth == 5);
    CHECK(o.seed == 42u);
    CHECK(o.outputDir == "out/dir");
    REQUIRE(o.envmap);
    CHECK(*o.envmap == "sky.hdr");
    CHECK_FALSE(o.editorScene);
}

TEST_CASE("parseCli: every flag in --flag=value form", "[cli]") {
    const CliOptions o = parseOk({"--scene=b.json", "--samples=3", "--width=7", "--height=9",
                                  "--max-depth=0", "--seed=4294967295", "--output=x", "--envmap=e.hdr"});
    CHECK(o.scene == std::string("b.json"));
    CHECK(o.samples == 3);
    CHECK(o.width == 7);
    CHECK(o.height == 9);
    CHECK(o.maxDepth == 0);
    CHECK(o.seed == 4294967295u);
    CHECK(o.outputDir == "x");
    CHECK(o.envmap == std::string("e.hdr"));
}

TEST_CASE("parseCli: a value containing '=' keeps everything after the first '='", "[cli]") {
    const CliOptions o = parseOk({"--output=a=b"});
    CHECK(o.outputDir == "a=b");
}

TEST_CASE("parseCli: each switch sets only its own field", "[cli]") {
    SECTION("--png") { CliOptions o = parseOk({"--png"}); CHECK(o.png); CHECK_FALSE(o.hdr); CHECK_FALSE(o.exr); }
    SECTION("--hdr") { CliOptions o = parseOk({"--hdr"}); CHECK(o.hdr); CHECK_FALSE(o.png); CHECK_FALSE(o.exr); }
    SECTION("--exr") { CliOptions o = parseOk({"--exr"}); CHECK(o.exr); CHECK_FALSE(o.png); CHECK_FALSE(o.hdr); }
    SECTION("--reinhard") { CliOptions o = parseOk({"--reinhard"}); CHECK(o.reinhard); CHECK_FALSE(o.png); }
    SECTION("--oidn") { CliOptions o = parseOk({"--oidn"}); CHECK(o.oidn); CHECK_FALSE(o.aovs); }
    SECTION("--aovs") { CliOptions o = parseOk({"--aovs"}); CHECK(o.aovs); CHECK_FALSE(o.oidn); }
    SECTION("--sky") { CliOptions o = parseOk({"--sky"}); CHECK(o.sky); CHECK_FALSE(o.envmap); }
    SECTION("--help") { CliOptions o = parseOk({"--help"}); CHECK(o.help); CHECK_FALSE(o.version); }
    SECTION("--version") { CliOptions o = parseOk({"--version"}); CHECK(o.version); CHECK_FALSE(o.help); }
    SECTION("all formats together") {
        CliOptions o = parseOk({"--png", "--hdr", "--exr"});
        CHECK(o.png);
        CHECK(o.hdr);
        CHECK(o.exr);
    }
}

TEST_CASE("parseCli: a switch given a value is an error", "[cli]") {
    CHECK(contains(parseError({"--png=yes"}), "--png"));
    CHECK(contains(parseError({"--png=yes"}), "takes no value"));
}

TEST_CASE("parseCli: --sky-preset names a look and implies --sky", "[cli]") {
    const CliOptions o = parseOk({"--sky-preset", "original"});
    CHECK(o.sky);
    REQUIRE(o.skyPreset);
    CHECK(*o.skyPreset == "original");
    CHECK(parseOk({"--sky-preset=default"}).skyPreset == std::optional<std::string>("default"));
    CHECK_FALSE(parseOk({"--sky"}).skyPreset);
    const std::string e = parseError({"--sky-preset", "dusk"});
    CHECK(contains(e, "--sky-preset"));
    CHECK(contains(e, "'dusk'"));
    CHECK(contains(e, "default, original"));
    CHECK(contains(cliUsage(), "--sky-preset"));
}

TEST_CASE("parseCli: later values override earlier ones", "[cli]") {
    const CliOptions o = parseOk({"--samples", "4", "--samples=9"});
    CHECK(o.samples == 9);
}

TEST_CASE("parseCli: a flag at the end without its value is an error naming the flag", "[cli]") {
    for (const char* flag : {"--scene", "--samples", "--width", "--height", "--max-depth", "--seed",
                             "--output", "--envmap"}) {
        INFO(flag);
        const std::string e = parseError({flag});
        CHECK(contains(e, flag));
        CHECK(contains(e, "missing value"));
    }
    // The value check must not read past the end even after other arguments.
    CHECK(contains(parseError({"--png", "--samples"}), "--samples"));
}

TEST_CASE("parseCli: non-integer values are rejected with the flag and the value", "[cli]") {
    for (const char* bad : {"abc", "", "12abc", "1.5", "1e3", " 8", "0x10"}) {
        INFO("value '" << bad << "'");
        const std::string e = parseError({"--samples", bad});
        CHECK(contains(e, "--samples"));
        CHECK(contains(e, std::string("'") + bad + "'"));
    }
    CHECK(contains(parseError({"--width=wide"}), "--width"));
    CHECK(contains(parseError({"--seed", "seven"}), "--seed"));
    CHECK(contains(parseError({"--max-depth", "deep"}), "--max-depth"));
}

TEST_CASE("parseCli: out-of-range values are rejected, bounds are accepted", "[cli]") {
    SECTION("samples") {
        CHECK(contains(parseError({"--samples", "0"}), "--samples"));
        CHECK(contains(parseError({"--samples", "-4"}), "'-4'"));
        CHECK(parseOk({"--samples", "1"}).samples == 1);
        CHECK(parseOk({"--samples", "16777216"}).samples == 16777216);
        CHECK(contains(parseError({"--samples", "16777217"}), "--samples"));
    }
    SECTION("width and height") {
        CHECK(contains(parseError({"--width", "20000"}), "--width"));
        CHECK(contains(parseError({"--width", "0"}), "--width"));
        CHECK(contains(parseError({"--height", "20000"}), "--height"));
        CHECK(contains(parseError({"--height", "-1"}), "--height"));
        CHECK(parseOk({"--width", "16384"}).width == 16384);
        CHECK(parseOk({"--height", "1"}).height == 1);
    }
    SECTION("max depth") {
        CHECK(parseOk({"--max-depth", "0"}).maxDepth == 0);
        CHECK(contains(parseError({"--max-depth", "-1"}), "--max-depth"));
    }
    SECTION("seed covers exactly the uint32 range") {
        CHECK(contains(parseError({"--seed", "-1"}), "--seed"));
        CHECK(parseOk({"--seed", "0"}).seed == 0u);
        CHECK(parseOk({"--seed", "4294967295"}).seed == 4294967295u);
        CHECK(contains(parseError({"--seed", "4294967296"}), "--seed"));
        // Far beyond long long: from_chars overflows, which must still be a clean error.
        CHECK(contains(parseError({"--seed", "99999999999999999999999"}), "--seed"));
    }
}

TEST_CASE("parseCli: an empty --output is an error", "[cli]") {
    CHECK(contains(parseError({"--output", ""}), "--output"));
    CHECK(contains(parseError({"--output="}), "--output"));
}

TEST_CASE("parseCli: unknown options are errors naming the option", "[cli]") {
    CHECK(contains(parseError({"--bogus"}), "--bogus"));
    CHECK(contains(parseError({"--bogus"}), "unknown option"));
    CHECK(contains(parseError({"--scene", "a.json", "-x"}), "-x"));
    CHECK(contains(parseError({"--bogus=3"}), "--bogus"));
    // A near miss of a real flag is still unknown.
    CHECK(contains(parseError({"--sample", "4"}), "--sample"));
}

TEST_CASE("parseCli: a bare argument is the editor's scene, a second one is an error", "[cli]") {
    const CliOptions o = parseOk({"my scene.json"});
    REQUIRE(o.editorScene);
    CHECK(*o.editorScene == "my scene.json");
    CHECK_FALSE(o.scene);

    // A lone "-" is not an option (conventionally stdin) and is taken as the positional.
    CHECK(parseOk({"-"}).editorScene == std::string("-"));

    const std::string e = parseError({"a.json", "b.json"});
    CHECK(contains(e, "b.json"));
    CHECK(contains(e, "unexpected argument"));

    // A value that looks like a file does not count as a positional.
    CHECK_FALSE(parseOk({"--scene", "a.json"}).editorScene);
    // A value starting with '-' is consumed as the flag's value, not parsed as an option.
    CHECK(parseOk({"--output", "-dir"}).outputDir == "-dir");
}

TEST_CASE("cliUsage documents every flag the parser accepts", "[cli]") {
    const std::string usage = cliUsage();
    for (const char* flag : {"--scene", "--samples", "--width", "--height", "--max-depth", "--seed",
                             "--output", "--png", "--hdr", "--exr", "--reinhard", "--sky", "--envmap",
                             "--oidn", "--aovs", "--help", "--version", "--variant", "--gpu", "--list-variants"}) {
        INFO(flag);
        CHECK(contains(usage, flag));
        // And the parser really accepts it: followed by "1", a flag taking a value takes it and a
        // switch leaves it as the positional argument; either way the parse succeeds.
        CliParseResult r = parseCli({flag, "1"});
        INFO(r.error);
        CHECK(r.options.has_value());
    }
}

TEST_CASE("parseCli: --sample-range and --crop (issue 17)", "[cli]") {
    const CliOptions o = parseOk({"--scene", "s.json", "--sample-range", "8:24", "--crop=3:17,0:5", "--variant", "2",
                                  "--gpu", "1", "--list-variants"});
    REQUIRE(o.sampleRange);
    CHECK(o.sampleRange->begin == 8);
    CHECK(o.sampleRange->end == 24);
    REQUIRE(o.crop);
    CHECK((o.crop->x0 == 3 && o.crop->x1 == 17 && o.crop->y0 == 0 && o.crop->y1 == 5));
    CHECK(o.variant == 2);
    CHECK(o.gpu == 1);
    CHECK(o.listVariants);
    CHECK(parseOk({"--sample-range", "0:16777216"}).sampleRange->end == 16777216u);
    for (const char* bad : {"4:4", "5:4", "4", ":4", "4:", "a:b", "-1:4", "0:16777217", "1:2:3"})
        CHECK(contains(parseError({"--sample-range", bad}), "--sample-range: expected <a>:<b>"));
    for (const char* bad : {"0:8", "0:8,", "8:0,0:8", "0:8,4:4", "0:8,0:x", "0:16385,0:8", "a"})
        CHECK(contains(parseError({"--crop", bad}), "--crop: expected <x0>:<x1>,<y0>:<y1>"));
}

TEST_CASE("parseCli: subcommands take their inputs and only their own options", "[cli]") {
    const CliOptions m = parseOk({"merge", "out.png", "a.exr", "b.exr", "--oidn", "--exr"});
    CHECK(m.command == "merge");
    CHECK(m.inputs == std::vector<std::string>{"out.png", "a.exr", "b.exr"});
    CHECK(m.oidn);
    CHECK(parseOk({"compare", "a.exr", "b.exr", "--map", "m.png"}).map == std::optional<std::string>("m.png"));
    CHECK(parseOk({"sheet", "layout.json"}).inputs.size() == 1);
    CHECK(contains(parseError({"merge", "out.png"}), "merge: expected <out> <part.exr>"));
    CHECK(contains(parseError({"merge", "o", "a.exr", "--samples", "4"}), "--samples is not an option of caustic merge"));
    CHECK(contains(parseError({"compare", "a", "b", "c"}), "compare: expected <image> <reference>, got 3"));
    CHECK(contains(parseError({"compare", "a", "b", "--oidn"}), "--oidn is not an option of caustic compare"));
    CHECK(contains(parseError({"sheet"}), "sheet: expected <layout.json>"));
    CHECK(parseOk({"merge", "--help"}).help);   // help needs no inputs
    // Not a subcommand anywhere but first: the editor's scene, as before.
    CHECK(parseOk({"merge.json"}).editorScene == std::optional<std::string>("merge.json"));
}
