// Pearson's chi-square goodness-of-fit test, as pbrt-v4 and Mitsuba 3 use it for samplers:
// observed sample counts per cell against the expected counts (the pdf integrated over each
// cell times the number of samples). Cells expecting fewer than 5 samples are pooled into one;
// a sample observed where nothing is expected fails at once. The significance level is Sidak-
// corrected for the number of tests in a suite: alpha_1 = 1 - (1 - alpha)^(1 / m).
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace caustic::test {

// Regularized upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a): the series for
// x < a + 1, otherwise the continued fraction (modified Lentz), both as in Abramowitz and
// Stegun 6.5.29 and 6.5.31.
inline double gammaQ(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double lnPrefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 10000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(lnPrefix);
    }
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(lnPrefix) * h;
}

// P(X >= statistic) for X ~ chi-square with `dof` degrees of freedom.
inline double chi2PValue(double statistic, int dof) { return gammaQ(0.5 * dof, 0.5 * statistic); }

struct Chi2Result {
    bool passed = false;
    double pValue = 0.0, statistic = 0.0;
    int dof = 0;
    std::string report;  // why it failed, with the observed and expected tables
};

// observed / expected: one entry per cell, laid out as rows x cols (for the printed tables).
inline Chi2Result chi2Test(const std::vector<double>& observed, const std::vector<double>& expected, int rows,
                           int cols, double significance, int testsInSuite) {
    Chi2Result r;
    const double alpha = 1.0 - std::pow(1.0 - significance, 1.0 / testsInSuite);
    double pooledObserved = 0.0, pooledExpected = 0.0, stat = 0.0;
    int cells = 0;
    std::ostringstream why;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] <= 0.0 && observed[i] > 0.0) {
            why << "cell " << i << " (row " << i / cols << ", col " << i % cols << ") has " << observed[i]
                << " samples where the pdf is zero\n";
            stat = INFINITY;
        } else if (expected[i] < 5.0) {
            pooledObserved += observed[i];
            pooledExpected += expected[i];
        } else {
            stat += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
            ++cells;
        }
    }
    if (pooledExpected >= 5.0) {
        stat += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
        ++cells;
    } else if (pooledObserved > 0.0 && cells > 0) {
        // Too little to form a cell of its own: the pooled remainder joins the statistic's last
        // term conservatively (its squared error counts against expected 5).
        stat += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / 5.0;
    }
    r.statistic = stat;
    r.dof = cells - 1;
    r.pValue = r.dof > 0 && std::isfinite(stat) ? chi2PValue(stat, r.dof) : 0.0;
    r.passed = r.dof > 0 && r.pValue >= alpha;
    if (!r.passed) {
        why << "chi-square " << stat << " with " << r.dof << " degrees of freedom: p = " << r.pValue
            << " < alpha = " << alpha << " (Sidak-corrected from " << significance << " over " << testsInSuite
            << " tests)\nobserved:\n";
        auto table = [&](const std::vector<double>& t) {
            for (int y = 0; y < rows; ++y) {
                for (int x = 0; x < cols; ++x) why << " " << static_cast<long long>(std::llround(t[size_t(y) * cols + x]));
                why << "\n";
            }
        };
        table(observed);
        why << "expected:\n";
        table(expected);
    }
    r.report = why.str();
    return r;
}

}  // namespace caustic::test
