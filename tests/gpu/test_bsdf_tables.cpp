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

#include <cmath>
#include <cstdio>

using namespace caustic;

namespace {

constexpr double kPi = 3.14159265358979323846;

double lambda(double cosTheta, double alpha) {
    const double c2 = cosTheta * cosTheta, t2 = (1.0 - c2) / c2;
    return 0.5 * (std::sqrt(1.0 + alpha * alpha * t2) - 1.0);
}

double quadratureAlbedo(double mu, double alpha) {
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
            sum += d * g2 * oh / mu * sh;  // sin(theta_h) from dh
        }
    }
    return sum * (kPi / 2 / kTheta) * (2 * kPi / kPhi);
}

}  // namespace

TEST_CASE("the GGX albedo table from the shader's microfacet code matches a quadrature", "[gpu][bsdf][materials]") {
    test::glContext();
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    std::string error;
    REQUIRE(computeGgxAlbedoTable(defaultShaderDir(), buffer, &error));
    const std::vector<float> t = readFloatBuffer(buffer);
    glDeleteBuffers(1, &buffer);
    constexpr int N = GGX_ALBEDO_TABLE_SIZE;
    REQUIRE(t.size() == size_t(N * N));
    for (float e : t) {
        CHECK(e > 0.0f);
        CHECK(e <= 1.0f);
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
