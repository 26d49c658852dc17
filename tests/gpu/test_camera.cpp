// The thin-lens camera against the thin-lens formula: a small emitter on the plane of focus
// stays sharp; off it, it spreads into a circle of confusion of radius
// aperture * |z - focal| / z (on the plane of focus); with squeeze s the bokeh is s times taller
// than wide; with n blades it is a regular n-gon. The pixel filters shape an edge's image by
// their own profile, and keep a flat field flat.
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace caustic;

namespace {

constexpr int kSize = 96;
constexpr float kFov = 20.0f, kFocal = 5.0f, kDepth = 2.5f, kBall = 0.05f;

Scene bokehScene(float aperture, float z, float ballRadius = kBall, float focal = kFocal) {
    Scene s;
    s.render.width = s.render.height = kSize;
    s.render.maxDepth = 0;  // only what the camera sees directly
    s.camera.position = glm::vec3(0.0f);
    s.camera.lookAt = glm::vec3(0.0f, 0.0f, -1.0f);
    s.camera.fovDegrees = kFov;
    s.camera.apertureRadius = aperture;
    s.camera.focalDistance = focal;
    s.materials.push_back({"glow", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(1.0f)});
    Object ball;
    ball.shape = Shape::Sphere;
    ball.material = "glow";
    ball.transform.translate = glm::vec3(0.0f, 0.0f, -z);
    ball.transform.scale = glm::vec3(ballRadius);
    s.objects.push_back(ball);
    return s;
}

struct Spot {
    double cx = 0, cy = 0, varX = 0, varY = 0, total = 0;
};

Spot measure(const Film& f) {
    Spot s;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            double v = f.mean[f.index(x, y)].g;
            s.total += v;
            s.cx += v * (x + 0.5);
            s.cy += v * (y + 0.5);
        }
    s.cx /= s.total;
    s.cy /= s.total;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            double v = f.mean[f.index(x, y)].g;
            s.varX += v * (x + 0.5 - s.cx) * (x + 0.5 - s.cx);
            s.varY += v * (y + 0.5 - s.cy) * (y + 0.5 - s.cy);
        }
    s.varX /= s.total;
    s.varY /= s.total;
    return s;
}

// Pixels per unit length on the plane of focus.
double pixelsPerUnit() { return (kSize / 2.0) / (kFocal * std::tan(glm::radians(kFov / 2.0))); }

// The variance (per axis) that the emitter's own size and the box pixel filter add to a spot:
// the ball's image on the plane of focus is a disk of radius kBall * focal / z (var r^2 / 4),
// the box filter a uniform pixel (var 1/12).
double ownVariance(float z) {
    double r = kBall * kFocal / z * pixelsPerUnit();
    return r * r / 4.0 + 1.0 / 12.0;
}

}  // namespace

TEST_CASE("thin lens: sharp on the plane of focus, circle of confusion off it", "[gpu][camera]") {
    auto renderer = test::makeRenderer();
    const float aperture = 0.5f;
    SECTION("on the plane of focus the aperture changes nothing") {
        Spot pin = measure(test::renderFilm(*renderer, bokehScene(0.0f, kFocal), 64));
        Spot lens = measure(test::renderFilm(*renderer, bokehScene(aperture, kFocal), 64));
        INFO("pinhole var " << pin.varX << ", lens var " << lens.varX);
        CHECK(lens.varX - ownVariance(kFocal) < 0.3);  // only the ball's own image and the pixel
        CHECK(std::abs(lens.varX - pin.varX) < 0.3);
        CHECK(lens.cx == Approx(kSize / 2.0).margin(0.2));
    }
    SECTION("off the plane of focus: radius aperture * |z - focal| / z") {
        Spot s = measure(test::renderFilm(*renderer, bokehScene(aperture, kDepth), 256));
        const double expected = aperture * std::abs(kDepth - kFocal) / kDepth * pixelsPerUnit();
        // A uniform disk of radius R has variance R^2 / 4 along each axis.
        const double measured = 2.0 * std::sqrt(s.varX - ownVariance(kDepth));
        const double measuredY = 2.0 * std::sqrt(s.varY - ownVariance(kDepth));
        INFO("circle of confusion radius: expected " << expected << " px, measured " << measured << " / " << measuredY);
        CHECK(measured == Approx(expected).epsilon(0.03));
        CHECK(measuredY == Approx(expected).epsilon(0.03));
        // Farther than the plane of focus blurs too, by the same formula.
        const float far = 10.0f;
        Spot f = measure(test::renderFilm(*renderer, bokehScene(aperture, far), 256));
        const double expectedFar = aperture * std::abs(far - kFocal) / far * pixelsPerUnit();
        CHECK(2.0 * std::sqrt(f.varX - ownVariance(far)) == Approx(expectedFar).epsilon(0.05));
    }
    SECTION("focused beyond what a float's square holds (1e20, 1e30): the circle of focus at infinity") {
        // The lens ray aims at a point ~focal away; its direction must not be normalised from that
        // point's distance, whose square overflows a float above ~1.8e19 (the image was black).
        // Focused at infinity, the radius in pixels is aperture / z * (size / 2) / tan(fov / 2)
        // (a smaller aperture here, so that the disk stays inside the image).
        const float small = 0.2f;
        for (const float focal : {1e20f, 1e30f}) {
            Spot s = measure(test::renderFilm(*renderer, bokehScene(small, kDepth, kBall, focal), 256));
            const double expected = small / kDepth * (kSize / 2.0) / std::tan(glm::radians(kFov / 2.0));
            const double ball = kBall / kDepth * (kSize / 2.0) / std::tan(glm::radians(kFov / 2.0));
            const double measured = 2.0 * std::sqrt(s.varX - (ball * ball / 4.0 + 1.0 / 12.0));
            INFO("focal " << focal << ": total " << s.total << ", radius expected " << expected << " px, measured "
                          << measured);
            REQUIRE(s.total > 0.0);
            CHECK(measured == Approx(expected).epsilon(0.03));
        }
    }
}

TEST_CASE("anamorphic bokeh: squeeze s makes it s times taller than wide", "[gpu][camera]") {
    auto renderer = test::makeRenderer();
    for (float squeeze : {1.0f, 2.0f}) {
        Scene s = bokehScene(0.5f, kDepth);
        s.camera.squeeze = squeeze;
        Spot spot = measure(test::renderFilm(*renderer, s, 256));
        double own = ownVariance(kDepth);
        double ratio = std::sqrt((spot.varY - own) / (spot.varX - own));
        INFO("squeeze " << squeeze << ": height / width " << ratio);
        CHECK(ratio == Approx(squeeze).epsilon(0.04));
    }
}

TEST_CASE("polygonal aperture: n blades give an n-gon", "[gpu][camera]") {
    // A smaller emitter (its image blurs the bokeh's outline by b = 1.1 px) and more samples,
    // so the outline can be measured: the support function h(theta) = max over lit pixels of
    // (p - centre) . (cos theta, sin theta), minus the blur.
    auto renderer = test::makeRenderer();
    const float ball = 0.02f;
    const double R = 0.5 * std::abs(kDepth - kFocal) / kDepth * pixelsPerUnit();
    const double b = ball * kFocal / kDepth * pixelsPerUnit();
    auto support = [](const Film& f, double angleDegrees) {
        Spot s = measure(f);
        double peak = 0;
        for (const glm::vec3& m : f.mean) peak = std::max(peak, double(m.g));
        const double c = std::cos(glm::radians(angleDegrees)), sn = std::sin(glm::radians(angleDegrees));
        double h = 0;
        for (int y = 0; y < f.height; ++y)
            for (int x = 0; x < f.width; ++x)
                if (f.mean[f.index(x, y)].g > 0.1 * peak)
                    h = std::max(h, (x + 0.5 - s.cx) * c + (y + 0.5 - s.cy) * sn + 0.5);
        return h;
    };
    auto litArea = [](const Film& f) {
        double peak = 0;
        int n = 0;
        for (const glm::vec3& m : f.mean) peak = std::max(peak, double(m.g));
        for (const glm::vec3& m : f.mean) n += m.g > 0.1 * peak;
        return double(n);
    };
    Scene round = bokehScene(0.5f, kDepth, ball);
    Film r = test::renderFilm(*renderer, round, 1024);
    Scene hex = round;
    hex.camera.blades = 6;
    Film h = test::renderFilm(*renderer, hex, 1024);
    const double rx = support(r, 0) - b, ry = support(r, 90) - b;
    const double hx = support(h, 0) - b, hy = support(h, 90) - b;
    INFO("R " << R << " px, blur " << b << " px; round " << rx << " x " << ry << "; hexagon " << hx << " x " << hy
              << "; lit areas " << litArea(r) << " / " << litArea(h));
    CHECK(rx == Approx(R).epsilon(0.06));
    CHECK(ry / rx == Approx(1.0).epsilon(0.05));
    // A hexagon with a vertex on the x axis has an edge whose normal is the y axis, at R cos 30
    // from the centre. (Along a vertex direction the threshold clips the blurred tip, so that
    // support is only checked to stick out beyond the edges, as a hexagon's corners do.)
    CHECK(hy == Approx(R * std::cos(glm::radians(30.0))).epsilon(0.04));
    CHECK(hx > 1.05 * hy);
    // Its area is 3 sqrt(3) / (2 pi) of the circle's (outlines widened by the blur b: Steiner's
    // formula A + P b + pi b^2).
    const double pi = std::numbers::pi;
    const double hexArea = 1.5 * std::sqrt(3.0) * R * R + 6.0 * R * b + pi * b * b;
    const double circleArea = pi * (R + b) * (R + b);
    CHECK(litArea(h) / litArea(r) == Approx(hexArea / circleArea).epsilon(0.04));
    // Rotating the blades by 30 degrees puts an edge normal on the x axis instead.
    hex.camera.bladeRotationDegrees = 30.0f;
    Film hr = test::renderFilm(*renderer, hex, 1024);
    CHECK(support(hr, 0) - b == Approx(R * std::cos(glm::radians(30.0))).epsilon(0.04));
    CHECK(support(hr, 90) - b > 1.05 * (support(hr, 0) - b));
}

TEST_CASE("pixel filters shape the image of an edge by their own profile", "[gpu][camera]") {
    // A vertical edge between black (left) and an emitter of radiance 1 (right) at x0 = 12.3
    // pixels. Every filter is importance-sampled, so a pixel centred at c sees the emitter in the
    // fraction of its samples whose offset dx has c + dx > x0: 1 - F(x0 - c), with F the
    // cumulative distribution of the filter's x marginal. The box spreads the edge over one pixel,
    // the tent over two, the Gaussian over three (its tails clamped at 1.5 pixels, where the
    // sampler folds them). A filter that were not applied, or applied with another width, would
    // give another profile. Rows are averaged; the tolerance is 5 standard errors of the row mean.
    constexpr int kW = 24, kH = 8;
    constexpr double kEdge = 12.3;
    auto boxCdf = [](double t) { return std::clamp(t + 0.5, 0.0, 1.0); };
    auto tentCdf = [](double t) {
        if (t <= -1.0) return 0.0;
        if (t >= 1.0) return 1.0;
        return t < 0.0 ? 0.5 * (1.0 + t) * (1.0 + t) : 1.0 - 0.5 * (1.0 - t) * (1.0 - t);
    };
    auto gaussianCdf = [](double t) {  // sigma 0.5, the mass beyond +-1.5 folded onto +-1.5
        if (t < -1.5) return 0.0;
        if (t >= 1.5) return 1.0;
        return 0.5 * std::erfc(-t / (0.5 * std::sqrt(2.0)));
    };
    struct Case { PixelFilter filter; double (*cdf)(double); int spread; };
    const Case cases[] = {{PixelFilter::Box, +boxCdf, 1}, {PixelFilter::Tent, +tentCdf, 2},
                          {PixelFilter::Gaussian, +gaussianCdf, 3}};
    auto renderer = test::makeRenderer();
    for (const Case& c : cases) {
        INFO("filter " << int(c.filter));
        Scene s;
        s.render.width = kW;
        s.render.height = kH;
        s.render.maxDepth = 0;
        s.render.filter = c.filter;
        s.camera.position = glm::vec3(0.0f);
        s.camera.lookAt = glm::vec3(0.0f, 0.0f, -1.0f);
        s.camera.fovAxis = FovAxis::X;
        s.camera.fovDegrees = 60.0f;
        // The image plane at distance 1 spans x in [-tan 30, tan 30]; pixel x maps linearly to it.
        const double tanX = std::tan(glm::radians(30.0));
        const double edgeX = (2.0 * kEdge / kW - 1.0) * tanX;
        s.materials.push_back({"glow", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(1.0f)});
        Object wall;
        wall.shape = Shape::Quad;
        wall.material = "glow";
        wall.transform.translate = glm::vec3(float(edgeX) + 5.0f, 0.0f, -1.0f);  // x in [edgeX, edgeX + 10]
        wall.transform.scale = glm::vec3(5.0f);
        s.objects.push_back(wall);
        const Film f = test::renderFilm(*renderer, s, 1024);
        int partial = 0;
        for (int x = 0; x < kW; ++x) {
            double mean = 0.0, var = 0.0;
            for (int y = 0; y < kH; ++y) {
                mean += f.mean[f.index(x, y)].g / kH;
                var += f.varianceOfMean[f.index(x, y)].g / (kH * kH);
            }
            const double expected = 1.0 - c.cdf(kEdge - (x + 0.5));
            INFO("column " << x << ": " << mean << " +- " << std::sqrt(var) << ", expected " << expected);
            CHECK(std::abs(mean - expected) <= 5.0 * std::sqrt(var) + 2e-3);
            partial += mean > 0.005 && mean < 0.995;
        }
        CHECK(partial == c.spread);  // how many pixels the edge is spread over
    }
}

TEST_CASE("pixel filters keep a uniform field uniform and the mean unchanged", "[gpu][camera]") {
    auto renderer = test::makeRenderer();
    for (PixelFilter filter : {PixelFilter::Box, PixelFilter::Tent, PixelFilter::Gaussian}) {
        Scene s;
        s.render.width = s.render.height = 8;
        s.render.filter = filter;
        s.environment.type = EnvironmentType::Constant;
        s.environment.radiance = glm::vec3(0.5f);
        Film f = test::renderFilm(*renderer, s, 4);
        for (const glm::vec3& m : f.mean) CHECK(m.g == Approx(0.5f));
    }
}
