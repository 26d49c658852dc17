// The GGX directional albedo table, computed on the GPU by the shaders' own microfacet code
// (shaders/bsdf/ggx_albedo.comp), against an independent quadrature in double precision here:
// E(mu, alpha) = integral over half-vectors h of D(h) G2(wo, wi) |wo.h| / cos(theta_o) dh
// (the F = 1 lobe's f cos, with dwi = 4 |wo.h| dh), D and G2 written out from their formulas
// (Walter et al. 2007, eq. 33; Heitz 2014, eqs. 72 and 99), on a midpoint grid in (theta_h, phi_h).
// Plus the two values known in closed form: 1 - ln 2 at alpha = 1 and normal incidence, and 1
// for a nearly smooth lobe.
#include "renderer/bsdf_tables.h"
#include "renderer/shader_loader.h"
#include "shaders/shared/layout.h"
#include "tests/gpu/gl_fixture.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace caustic;

namespace {

constexpr double kPi = 3.14159265358979323846;

double lambda(double cosTheta, double alpha) {
    const double c2 = cosTheta * cosTheta, t2 = (1.0 - c2) / c2;
    return 0.5 * (std::sqrt(1.0 + alpha * alpha * t2) - 1.0);
}

// Unpolarised Fresnel of a dielectric (light from outside), written from the equations.
double fresnel(double ci, double eta) {
    const double s2t = (1.0 - ci * ci) / (eta * eta);
    if (s2t >= 1.0) return 1.0;
    const double ct = std::sqrt(1.0 - s2t);
    const double rs = (ci - eta * ct) / (ci + eta * ct), rp = (eta * ci - ct) / (eta * ci + ct);
    return 0.5 * (rs * rs + rp * rp);
}

// eta 0: F = 1; otherwise the dielectric reflection lobe's albedo.
double quadratureAlbedo(double mu, double alpha, double eta = 0.0) {
    const double sinO = std::sqrt(1.0 - mu * mu);
    constexpr int kTheta = 3000, kPhi = 256;
    double sum = 0.0;
    for (int i = 0; i < kTheta; ++i) {
        const double th = (i + 0.5) * (kPi / 2) / kTheta;
        const double ch = std::cos(th), sh = std::sin(th);
        const double a2 = alpha * alpha;
        const double d = a2 / (kPi * std::pow(sh * sh + a2 * ch * ch, 2.0));
        for (int j = 0; j < kPhi; ++j) {
            const double ph = (j + 0.5) * 2 * kPi / kPhi;
            const double hx = sh * std::cos(ph), hz = ch;  // wo lies in the xz plane: h.y drops out
            const double oh = sinO * hx + mu * hz;
            if (oh <= 0.0) continue;
            const double wiz = 2.0 * oh * hz - mu;
            if (wiz <= 0.0) continue;
            const double g2 = 1.0 / (1.0 + lambda(mu, alpha) + lambda(wiz, alpha));
            sum += d * g2 * oh / mu * sh * (eta > 0.0 ? fresnel(oh, eta) : 1.0);  // sin(theta_h) from dh
        }
    }
    return sum * (kPi / 2 / kTheta) * (2 * kPi / kPhi);
}

// Estevez and Kulla 2017's fitted Lambda for the Charlie sheen (their table of coefficients).
double sheenLambda(double x, double r) {
    const double t = (1.0 - r) * (1.0 - r);
    auto mix = [&](double a1, double a0) { return a1 + (a0 - a1) * t; };
    auto L = [&](double y) {
        return mix(21.5473, 25.3245) / (1.0 + mix(3.82987, 3.32435) * std::pow(y, mix(0.19823, 0.16801))) +
               mix(-1.97760, -1.27393) * y + mix(-4.32054, -4.85967);
    };
    return x < 0.5 ? std::exp(L(x)) : std::exp(2.0 * L(0.5) - L(1.0 - x));
}

// The sheen lobe's albedo (Charlie D with Estevez-Kulla shadowing; shaders/bsdf/layer_lobes.glsl)
// by the midpoint rule over wi's hemisphere.
double sheenQuadrature(double mu, double r) {
    r = std::max(r, 0.07);
    const double sinO = std::sqrt(1.0 - mu * mu);
    constexpr int kTheta = 1024, kPhi = 256;
    double sum = 0.0;
    for (int i = 0; i < kTheta; ++i) {
        const double ti = (i + 0.5) * (kPi / 2) / kTheta, ci = std::cos(ti), si = std::sin(ti);
        for (int j = 0; j < kPhi; ++j) {
            const double ph = (j + 0.5) * 2 * kPi / kPhi;
            double hx = sinO + si * std::cos(ph), hy = si * std::sin(ph), hz = mu + ci;
            const double len = std::sqrt(hx * hx + hy * hy + hz * hz);
            hz /= len;
            const double sin2 = std::max(0.0, 1.0 - hz * hz);
            const double d = (2.0 + 1.0 / r) * std::pow(sin2, 0.5 / r) / (2.0 * kPi);
            const double g = 1.0 / (1.0 + sheenLambda(mu, r) + sheenLambda(ci, r));
            sum += d * g / (4.0 * mu * ci) * ci * si;
        }
    }
    return sum * (kPi / 2 / kTheta) * (2 * kPi / kPhi);
}

// Every BSDF table, as the renderer computes it (shaders/bsdf/*.comp).
std::vector<float> computedTables() {
    test::glContext();
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    std::string error;
    const bool ok = computeBsdfTables(defaultShaderDir(), buffer, &error);
    INFO(error);
    REQUIRE(ok);
    std::vector<float> t = readFloatBuffer(buffer);
    glDeleteBuffers(1, &buffer);
    REQUIRE(t.size() == size_t(BSDF_TABLE_FLOATS));
    return t;
}

}  // namespace

TEST_CASE("the GGX albedo table from the shader's microfacet code matches a quadrature", "[gpu][bsdf][materials]") {
    const std::vector<float> t = computedTables();
    constexpr int N = GGX_ALBEDO_TABLE_SIZE;
    for (int i = 0; i < N * N; ++i) {
        CHECK(t[size_t(i)] > 0.0f);
        CHECK(t[size_t(i)] <= 1.0f);
    }
    // alpha = 1, normal incidence: 1 - ln 2 (D = 1/pi, integrated by hand).
    CHECK(t[size_t(N - 1) * N + N - 1] == Approx(1.0 - std::log(2.0)).margin(2e-3));
    // Nearly smooth (alpha = 1e-3): everything is reflected, at every angle but the most grazing.
    for (int i = 2; i < N; ++i) CHECK(t[size_t(i)] == Approx(1.0).margin(2e-3));
    // Entries across the table against the quadrature.
    for (int j : {6, 12, 20, 31})
        for (int i : {3, 10, 20, 31}) {
            const double alpha = double(j) / (N - 1), mu = double(i) / (N - 1);
            const double reference = quadratureAlbedo(mu, alpha);
            INFO("mu " << mu << " alpha " << alpha << ": table " << t[size_t(j) * N + size_t(i)] << ", quadrature "
                       << reference);
            CHECK(t[size_t(j) * N + size_t(i)] == Approx(reference).margin(3e-3));
        }
}

TEST_CASE("the surface material's albedo tables from the shader's lobes match quadratures", "[gpu][bsdf][materials]") {
    const std::vector<float> t = computedTables();
    constexpr int N = GGX_ALBEDO_TABLE_SIZE, I = SURFACE_TABLE_IOR;
    for (int i = BSDF_TABLE_DIELECTRIC; i < BSDF_TABLE_FLOATS; ++i) {
        CHECK(t[size_t(i)] >= 0.0f);
        CHECK(t[size_t(i)] <= 1.0f);
    }
    // Slice k holds ior (1 + x) / (1 - x), x = k / (2 (I - 1)); slice 0 is ior 1 (nothing reflects).
    for (int i = 0; i < N * N; ++i) CHECK(t[size_t(BSDF_TABLE_DIELECTRIC + i)] == Approx(0.0).margin(1e-4));
    double worst = 0.0;
    for (int k : {3, 8, 15})
        for (int j : {1, 6, 16, 31})
            for (int i : {2, 10, 20, 31}) {
                const double x = 0.5 * k / (I - 1), eta = (1.0 + x) / (1.0 - x);
                const double alpha = std::max(double(j) / (N - 1), 1e-3), mu = double(i) / (N - 1);
                const double reference = quadratureAlbedo(mu, alpha, eta);
                const float e = t[size_t(BSDF_TABLE_DIELECTRIC + (k * N + j) * N + i)];
                worst = std::max(worst, std::abs(e - reference));
                INFO("ior " << eta << " mu " << mu << " alpha " << alpha << ": table " << e << ", quadrature " << reference);
                CHECK(e == Approx(reference).margin(3e-3));
            }
    std::printf("surface tables: dielectric E, largest difference to the quadrature %.2e\n", worst);
    // Smooth glass of ior 1.5 at normal incidence reflects F0 = 0.04.
    {
        const double x = 0.2, eta = (1.0 + x) / (1.0 - x);  // = 1.5: x = 0.2 is slice 0.4 (I - 1) = 6
        REQUIRE(std::abs(eta - 1.5) < 1e-9);
        CHECK(t[size_t(BSDF_TABLE_DIELECTRIC + (6 * N + 0) * N + N - 1)] == Approx(0.04).margin(1e-3));
    }
    worst = 0.0;
    for (int j : {2, 8, 16, 31})
        for (int i : {2, 10, 20, 31}) {
            const double r = double(j) / (N - 1), mu = double(i) / (N - 1);
            const double reference = sheenQuadrature(mu, r);
            const float e = t[size_t(BSDF_TABLE_SHEEN + j * N + i)];
            worst = std::max(worst, std::abs(e - reference));
            INFO("sheen r " << r << " mu " << mu << ": table " << e << ", quadrature " << reference);
            CHECK(e == Approx(reference).margin(3e-3));
        }
    std::printf("surface tables: sheen E, largest difference to the quadrature %.2e\n", worst);
    // The averages are 2 int E mu dmu of the linear interpolant (trapezoid-exact), checked by
    // Simpson's rule on a fine grid of that interpolant.
    for (int k : {0, 6, 15})
        for (int j : {0, 10, 31}) {
            const float* row = &t[size_t(BSDF_TABLE_DIELECTRIC + (k * N + j) * N)];
            double sum = 0.0;
            constexpr int kFine = 3100;
            for (int q = 0; q <= kFine; ++q) {
                const double mu = double(q) / kFine, p = mu * (N - 1);
                const int i0 = std::min(int(p), N - 2);
                const double e = row[i0] + (row[i0 + 1] - row[i0]) * (p - i0);
                const double wgt = q == 0 || q == kFine ? 1.0 : (q % 2 ? 4.0 : 2.0);
                sum += wgt * 2.0 * e * mu;
            }
            sum /= 3.0 * kFine;
            CHECK(t[size_t(BSDF_TABLE_DIELECTRIC_AVG + k * N + j)] == Approx(sum).margin(1e-4));
        }
}
