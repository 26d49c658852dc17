// The statistics the sampler tests rely on, checked against known values.
#include "tests/support/chi2.h"

#include <catch2/catch.hpp>

#include <random>

using namespace caustic::test;

TEST_CASE("chi-square p-values match tabulated quantiles", "[cpu][chi2]") {
    // Upper quantiles of the chi-square distribution (e.g. NIST/SEMATECH e-Handbook, table 1.3.6.7.4).
    CHECK(chi2PValue(3.841, 1) == Approx(0.05).epsilon(1e-3));
    CHECK(chi2PValue(18.307, 10) == Approx(0.05).epsilon(1e-3));
    CHECK(chi2PValue(23.209, 10) == Approx(0.01).epsilon(1e-3));
    CHECK(chi2PValue(124.342, 100) == Approx(0.05).epsilon(1e-3));
    CHECK(chi2PValue(0.0, 5) == Approx(1.0));
}

TEST_CASE("chi-square test accepts a fair die and rejects a loaded one", "[cpu][chi2]") {
    std::mt19937 rng(42);
    const int n = 60000;
    std::vector<double> fair(6, 0.0), loaded(6, 0.0), expected(6, n / 6.0);
    std::uniform_int_distribution<int> die(0, 5);
    for (int i = 0; i < n; ++i) {
        fair[die(rng)] += 1;
        int face = die(rng);
        loaded[(face == 5 && i % 10 == 0) ? 0 : face] += 1;  // 1/60 of all throws: a six becomes a one
    }
    Chi2Result f = chi2Test(fair, expected, 1, 6, 0.01, 1);
    INFO(f.report);
    CHECK(f.passed);
    Chi2Result l = chi2Test(loaded, expected, 1, 6, 0.01, 1);
    CHECK_FALSE(l.passed);
    CHECK(l.report.find("observed") != std::string::npos);
    // A sample where the pdf is zero fails regardless of the rest.
    std::vector<double> zeroCell = expected;
    zeroCell[2] = 0.0;
    std::vector<double> obs = expected;
    CHECK_FALSE(chi2Test(obs, zeroCell, 1, 6, 0.01, 1).passed);
}
