// The film read-back in bands of rows (renderer/renderer.h readBackBands): one GL read takes a
// 32-bit byte count, which a 16384x16384 RGBA float film (4 GiB) would overflow (issue 12).
#include "renderer/renderer.h"

#include <catch2/catch.hpp>

#include <climits>

using namespace caustic;

TEST_CASE("read-back bands cover every row in order, each within the byte limit and a GLsizei", "[limits]") {
    struct Case {
        int w, h;
        std::size_t maxBytes;
    };
    for (const Case c : {Case{16384, 16384, kMaxReadBackBytes}, Case{16384, 8192, kMaxReadBackBytes},
                         Case{256, 256, kMaxReadBackBytes}, Case{1000, 7, 3 * 1000 * 16}, Case{5, 3, 1},
                         Case{16384, 16384, std::size_t(INT_MAX)}}) {
        INFO(c.w << "x" << c.h << " at most " << c.maxBytes);
        const std::vector<RowBand> bands = readBackBands(c.w, c.h, 16, c.maxBytes);
        int next = 0;
        for (const RowBand& b : bands) {
            CHECK(b.y0 == next);
            CHECK(b.rows >= 1);
            const std::size_t bytes = std::size_t(b.rows) * std::size_t(c.w) * 16;
            CHECK(bytes <= std::size_t(INT_MAX));
            if (b.rows > 1) CHECK(bytes <= c.maxBytes);
            next += b.rows;
        }
        CHECK(next == c.h);
    }
    CHECK(readBackBands(256, 256, 16).size() == 1);               // the usual case: one read
    CHECK(readBackBands(16384, 16384, 16).size() == 4);           // 4 GiB in 1 GiB bands
    CHECK(readBackBands(0, 10, 16).empty());
}
