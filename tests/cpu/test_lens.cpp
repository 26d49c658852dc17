// Lens prescriptions (renderer/lens.h): the reader's messages, and the optics of each shipped
// design checked against independent computations:
//   - paraxial: the effective focal length and back focal distance from the y-nu trace equal those
//     of the ray-transfer (ABCD) matrix product written here;
//   - real rays: the f-number measured from the marginal ray of a bundle parallel to the axis (the
//     widest that passes every aperture: N = 1 / (2 sin theta) of its exit angle) equals the
//     paraxial one (EFL over the entrance pupil) within the design's aberration, and the design's
//     stated f-number;
//   - near the axis, real rays focus at the paraxial back focal distance.
#include "renderer/lens.h"
#include "tests/support/lens_pupil.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>
#include <string>

using namespace caustic;

namespace {

LensSystem shipped(const std::string& name) {
    LensSystem lens;
    std::string error;
    const bool ok = readLensFile(std::string(CAUSTIC_SOURCE_DIR) + "/assets/lenses/" + name, &lens, &error);
    INFO(error);
    REQUIRE(ok);
    return lens;
}

// The ray-transfer matrix of the whole system in (y, n u) form, first surface to last:
// refraction [[1, 0], [-(n' - n) / R, 1]], transfer [[1, t / n'], [0, 1]].
struct Abcd { double a = 1, b = 0, c = 0, d = 1; };
Abcd times(const Abcd& m, const Abcd& r) {  // m * r
    return {m.a * r.a + m.b * r.c, m.a * r.b + m.b * r.d, m.c * r.a + m.d * r.c, m.c * r.b + m.d * r.d};
}
Abcd systemMatrix(const LensSystem& lens) {
    Abcd m;
    double n = 1.0;
    for (std::size_t i = 0; i < lens.surfaces.size(); ++i) {
        const LensSurface& s = lens.surfaces[i];
        const double power = s.radius == 0.0 ? 0.0 : (s.ior - n) / s.radius;
        m = times({1.0, 0.0, -power, 1.0}, m);
        n = s.ior;
        if (i + 1 < lens.surfaces.size()) m = times({1.0, s.thickness / n, 0.0, 1.0}, m);
    }
    return m;
}

// The f-number from real rays: the widest bundle parallel to the axis that passes (bisection on
// the height), its marginal ray's exit angle.
double tracedFNumber(const LensSystem& lens) {
    double lo = 0.0, hi = lens.surfaces.front().aperture;
    for (int k = 0; k < 60; ++k) {
        const double h = 0.5 * (lo + hi);
        (traceFromScene(lens, {{0.0, h, -10.0}, {0.0, 0.0, 1.0}}) ? lo : hi) = h;
    }
    const auto out = traceFromScene(lens, {{0.0, lo, -10.0}, {0.0, 0.0, 1.0}});
    REQUIRE(out);
    const double sinTheta = std::sqrt(out->d.x * out->d.x + out->d.y * out->d.y);
    return 1.0 / (2.0 * sinTheta);
}

}  // namespace

TEST_CASE("lens files: the shipped designs read, and bad rows are refused naming file and line", "[cpu][lens]") {
    const LensSystem dgauss = shipped("dgauss-50mm.lens");
    CHECK(dgauss.surfaces.size() == 11);
    CHECK(dgauss.stopIndex() == 5);
    CHECK(dgauss.name == "double Gauss 50 mm f/2");
    CHECK(dgauss.source.find("Modern Lens Design") != std::string::npos);
    for (const char* f : {"telephoto-250mm.lens", "wide-22mm.lens", "fisheye-10mm.lens"}) CHECK(shipped(f).stopIndex() >= 0);
    auto error = [](const std::string& text) {
        LensSystem l;
        std::string e;
        CHECK_FALSE(parseLensSystem(text, "bad.lens", &l, &e));
        return e;
    };
    CHECK(error("10 1 1.5 5\n-10 0 1\n") == "bad.lens:2: expected radius, thickness, index, aperture diameter [and Abbe "
                                           "number]: 4 or 5 numbers, got 3");
    CHECK(error("# a\n10 1 1.5 5\n-10 0 x 5\n").find("bad.lens:3: 'x' is not a number") == 0);
    CHECK(error("10 -1 1.5 5\n-10 0 1 5\n").find("bad.lens:1: thickness") == 0);
    CHECK(error("10 1 1.5 0\n-10 0 1 5\n").find("bad.lens:1: aperture") == 0);
    CHECK(error("10 1 0.5 5\n-10 0 1 5\n").find("bad.lens:1: index") == 0);
    CHECK(error("2 1 1.5 5\n-10 0 1 5\n").find("bad.lens:1: aperture diameter larger") == 0);
    CHECK(error("10 1 1.5 5\n0 1 0 5\n0 1 0 5\n-10 0 1 5\n").find("bad.lens:3: a second aperture stop") == 0);
    CHECK(error("10 1 1.5 5 stop\n-10 0 1 5\n").find("the aperture stop must be flat") != std::string::npos);
    CHECK(error("10 1 1.5 5\n").find("at least two surfaces") != std::string::npos);
    CHECK(error("10 1 nan 5\n-10 0 1 5\n").find("not finite") != std::string::npos);
    LensSystem l;
    std::string e;
    CHECK_FALSE(readLensFile("/nonexistent/x.lens", &l, &e));
    CHECK(e == "/nonexistent/x.lens: cannot open the lens file");
}

TEST_CASE("lens optics: paraxial focal lengths equal the ABCD matrix's, f-numbers the traced marginal rays'",
          "[cpu][lens]") {
    struct Case { const char* file; double efl, fNumber, eflTolerance; };
    // The stated focal lengths and f-numbers of the designs (their names); the wide angle's and the
    // fisheye's scaled tables land a little off their nominal focal lengths.
    for (const Case& k : {Case{"dgauss-50mm.lens", 50.0, 2.0, 0.05}, Case{"telephoto-250mm.lens", 250.0, 5.6, 0.05},
                          Case{"wide-22mm.lens", 22.0, 0.0, 0.15}, Case{"fisheye-10mm.lens", 10.0, 0.0, 0.4}}) {
        INFO(k.file);
        const LensSystem lens = shipped(k.file);
        const auto p = paraxialAnalysis(lens);
        REQUIRE(p);
        const Abcd m = systemMatrix(lens);
        // Behind the last surface (air): EFL = -1 / C, BFD = -A / C.
        const double efl = -1.0 / m.c, bfd = -m.a / m.c;
        CHECK(p->efl == Approx(efl).epsilon(1e-12));
        CHECK(p->bfd == Approx(bfd).epsilon(1e-12));
        CHECK(std::abs(m.a * m.d - m.b * m.c - 1.0) < 1e-12);  // det = n / n' = 1, air on both sides
        CHECK(std::abs(p->efl / k.efl - 1.0) < k.eflTolerance);
        const double traced = tracedFNumber(lens);
        std::printf("lens %-22s EFL %8.3f mm  BFD %8.3f mm  f/%.3f paraxial  f/%.3f traced\n", k.file, p->efl, p->bfd,
                    p->fNumber, traced);
        CHECK(traced == Approx(p->fNumber).epsilon(0.05));
        if (k.fNumber > 0.0) CHECK(traced == Approx(k.fNumber).epsilon(0.1));
        // Near the axis real rays cross it at the paraxial focus (spherical aberration is of order h^2).
        const double h = 0.01 * p->entrancePupilDiameter;
        const auto out = traceFromScene(lens, {{0.0, h, -10.0}, {0.0, 0.0, 1.0}});
        REQUIRE(out);
        const double zCross = out->o.z - out->o.y / out->d.y * out->d.z;
        CHECK(zCross - surfaceVertices(lens).back() == Approx(p->bfd).epsilon(1e-3));
        // A ray from the film through the centre of the aperture goes back out: the trace is reversible.
        const auto back = traceFromFilm(lens, {{0.0, 0.0, surfaceVertices(lens).back() + p->bfd}, glm::normalize(glm::dvec3(0.0, -out->d.y, -out->d.z))});
        REQUIRE(back);
        CHECK(std::abs(back->d.y) < 1e-6);      // leaves parallel to the axis
        CHECK(back->o.y == Approx(h).epsilon(1e-3));
    }
}

namespace {

LensCamera camera(const LensSystem& lens, double focusMm, double fNumber, int blades = 0, bool dispersion = true) {
    LensCameraSettings s;
    s.focusDistanceMm = focusMm;
    s.fNumber = fNumber;
    s.blades = blades;
    s.dispersion = dispersion;
    LensCamera cam;
    std::string error;
    const bool ok = prepareLensCamera(lens, s, &cam, &error);
    INFO(error);
    REQUIRE(ok);
    return cam;
}

// Rays from an axial point `distance` mm in front of the film through a grid over the first
// surface's aperture, at wavelength nm; where those that pass meet the film, as (x, y).
std::vector<glm::dvec2> filmSpot(const LensCamera& cam, double distance, double nm) {
    std::vector<glm::dvec2> hits;
    const glm::dvec3 object(0.0, 0.0, cam.filmZ - distance);
    const double r = 0.5 * cam.lens.surfaces.front().aperture;
    constexpr int n = 240;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 target(r * (2.0 * (i + 0.5) / n - 1.0), r * (2.0 * (j + 0.5) / n - 1.0), 0.0);
            const auto out = traceFromScene(cam.lens, {object, glm::normalize(target - object)}, nm);
            if (!out) continue;
            const double t = (cam.filmZ - out->o.z) / out->d.z;
            hits.push_back(glm::dvec2(out->o.x + t * out->d.x, out->o.y + t * out->d.y));
        }
    return hits;
}

double rmsRadius(const std::vector<glm::dvec2>& hits) {
    glm::dvec2 mean(0.0);
    for (const glm::dvec2& h : hits) mean += h;
    mean /= double(hits.size());
    double sum = 0.0;
    for (const glm::dvec2& h : hits) sum += glm::dot(h - mean, h - mean);
    return std::sqrt(sum / double(hits.size()));
}

// The exit pupil, paraxially and independently of renderer/lens.cpp: the stop imaged by the
// surfaces behind it. Returns (its position behind the last vertex, its radius) for a stop of
// radius `stopRadius`.
glm::dvec2 exitPupil(const LensSystem& lens, double stopRadius) {
    const int stop = lens.stopIndex();
    auto through = [&](double y, double u) {  // from the stop's plane to behind the last vertex
        double n = 1.0, nu = u;
        y += lens.surfaces[std::size_t(stop)].thickness * u;
        for (std::size_t i = std::size_t(stop) + 1; i < lens.surfaces.size(); ++i) {
            const LensSurface& s = lens.surfaces[i];
            nu -= y * (s.ior - n) * (s.radius == 0.0 ? 0.0 : 1.0 / s.radius);
            n = s.ior;
            if (i + 1 < lens.surfaces.size()) y += s.thickness * nu / n;
        }
        return glm::dvec2(y, nu / n);
    };
    const glm::dvec2 chief = through(0.0, 0.01), marginal = through(stopRadius, 0.0);
    const double position = -chief.x / chief.y;
    return {position, std::abs(marginal.x + marginal.y * position)};
}

}  // namespace

TEST_CASE("lens camera: focused by moving the lens, a point at the focus distance images to a spot, and defocus gives "
          "geometric optics' circle of confusion", "[cpu][lens]") {
    // (Not the singlet: its spherical aberration makes the defocused disc uneven even at f/8.)
    for (const char* file : {"dgauss-50mm.lens", "telephoto-250mm.lens", "wide-22mm.lens"}) {
        INFO(file);
        const LensSystem lens = shipped(file);
        const double focus = 3000.0;
        const LensCamera cam = camera(lens, focus, 8.0, 0, false);
        CHECK(cam.fNumber == 8.0);
        CHECK(cam.focusDistanceMm == Approx(focus).epsilon(1e-9));
        CHECK(cam.notes.empty());
        // In focus: the spot is within a few Airy radii (1.22 lambda N = 5.7 um at f/8): the
        // designs' residual aberration, stopped down.
        const std::vector<glm::dvec2> sharp = filmSpot(cam, focus, kLineD);
        REQUIRE(sharp.size() > 100);
        const double sharpRms = rmsRadius(sharp);
        // Out of focus (a point at 12 focal lengths, at most 1.5 m): a disc whose diameter is the
        // exit pupil's times the focus error over the image's distance from the pupil (similar
        // triangles); far enough out of focus that the autofocus's own shift (spherical
        // aberration's, a few um) does not count.
        const double near = std::min(1500.0, 12.0 * cam.efl);
        const std::vector<glm::dvec2> blurred = filmSpot(cam, near, kLineD);
        const LensMatrix m = paraxialMatrix(cam.lens);
        const double t = cam.lens.surfaces.back().thickness;
        const double s = near - cam.lens.length() - t;   // in front of the first vertex, the lens where it is
        const double image = -(m.a * s + m.b) / (m.c * s + m.d);  // behind the last vertex
        const glm::dvec2 pupil = exitPupil(cam.lens, cam.stopRadius);
        const double coc = 2.0 * pupil.y * std::abs(image - t) / (image - pupil.x);
        const double blurredRms = rmsRadius(blurred);
        std::printf("lens %-22s focused at 3 m, f/8: spot %.4f mm rms; at %.0f mm: %.4f mm rms, geometric optics' "
                    "disc %.4f mm across (rms %.4f)\n", file, sharpRms, near, blurredRms, coc, coc / (2.0 * std::sqrt(2.0)));
        CHECK(sharpRms < 0.01);
        CHECK(sharpRms < 0.1 * blurredRms);
        // A uniform disc of diameter c has an rms radius of c / (2 sqrt 2).
        CHECK(blurredRms == Approx(coc / (2.0 * std::sqrt(2.0))).epsilon(0.05));
    }
    // Nearer than it can focus: its closest focus, said in a note; wider than it opens: wide open.
    const LensCamera close = camera(shipped("dgauss-50mm.lens"), 50.0, 1.0);
    CHECK(close.notes.size() == 2);
    CHECK(close.fNumber == Approx(close.fNumberOpen));
    CHECK(close.focusDistanceMm > 150.0);   // about 4 f for a lens focused by moving it
    CHECK(close.focusDistanceMm < 400.0);
    const LensCamera closest = camera(shipped("dgauss-50mm.lens"), close.focusDistanceMm * 1.001, 0.0);
    CHECK(closest.notes.empty());           // and just beyond it, it focuses
}

TEST_CASE("lens camera: the exit-pupil bounds hold every ray that passes, the weight's mean is 1 at the film's "
          "centre, and the stop's blades shape the pupil", "[cpu][lens]") {
    for (const char* file : {"dgauss-50mm.lens", "telephoto-250mm.lens", "wide-22mm.lens", "fisheye-10mm.lens"}) {
        INFO(file);
        const LensCamera cam = camera(shipped(file), 5000.0, 0.0);
        // No ray outside the bound of its film radius passes: a fine grid over the rear element.
        int outside = 0, passing = 0;
        const double extent = 0.75 * cam.lens.surfaces.back().aperture;
        for (double r : {0.0, 0.3 * cam.filmRadius, 0.7 * cam.filmRadius, 0.99 * cam.filmRadius}) {
            const glm::dvec4 b = cam.pupilBounds[std::size_t(std::min(int(r / cam.filmRadius * kLensPupilBins),
                                                                       kLensPupilBins - 1))];
            constexpr int n = 160;
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const glm::dvec3 p(extent * (2.0 * (i + 0.5) / n - 1.0), extent * (2.0 * (j + 0.5) / n - 1.0),
                                       cam.vertexZ.back());
                    const glm::dvec3 o(r, 0.0, cam.filmZ);
                    if (!traceFromFilm(cam.lens, {o, glm::normalize(p - o)})) continue;
                    ++passing;
                    outside += p.x < b.x || p.x > b.z || p.y < b.y || p.y > b.w;
                }
        }
        CHECK(passing > 1000);
        CHECK(outside == 0);
        double sum = 0.0;
        for (int j = 0; j < 64; ++j)
            for (int i = 0; i < 64; ++i) {
                double w = 0.0;
                lensCameraRay(cam, glm::dvec2(0.0), glm::dvec2((i + 0.5) / 64.0, (j + 0.5) / 64.0), -1, &w);
                sum += w;
            }
        CHECK(sum / 4096.0 == Approx(1.0).epsilon(0.02));
        const double fraction = lensPassFraction(cam);
        std::printf("lens %-22s wide open, focused at 5 m: %.1f %% of camera rays reach the scene\n", file, 100.0 * fraction);
        CHECK(fraction > 0.3);
    }
    // Six blades inscribed in the round stop's circle pass (3 sqrt(3) / 2) / pi of its rays.
    const LensSystem dgauss = shipped("dgauss-50mm.lens");
    const LensCamera round = camera(dgauss, 5000.0, 4.0, 0), hexagon = camera(dgauss, 5000.0, 4.0, 6);
    auto passed = [](const LensCamera& cam) {
        int count = 0;
        for (int j = 0; j < 200; ++j)
            for (int i = 0; i < 200; ++i) {
                double w = 0.0;
                count += lensCameraRay(cam, glm::dvec2(0.0), glm::dvec2((i + 0.5) / 200.0, (j + 0.5) / 200.0), -1, &w)
                             .has_value();
            }
        return double(count);
    };
    const double ratio = passed(hexagon) / passed(round) *
                         ((hexagon.pupilBounds[0].z - hexagon.pupilBounds[0].x) * (hexagon.pupilBounds[0].w - hexagon.pupilBounds[0].y)) /
                         ((round.pupilBounds[0].z - round.pupilBounds[0].x) * (round.pupilBounds[0].w - round.pupilBounds[0].y));
    CHECK(ratio == Approx(1.5 * std::sqrt(3.0) / std::numbers::pi).epsilon(0.02));
    // The bounds, found on +x and turned with the film point, hold a polygonal stop at every
    // angle: near the axis the hexagon passes the same share whatever the film point's angle
    // (the box of its +x view was cos 30 degrees too short at 30 degrees).
    auto passingArea = [&](const LensCamera& cam, double angle) {
        const glm::dvec2 film = 0.5 * glm::dvec2(std::cos(angle), std::sin(angle));
        const glm::dvec4 b = cam.pupilBounds[0];
        int count = 0;
        constexpr int n = 200;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                double w = 0.0;
                count += lensCameraRay(cam, film, glm::dvec2((i + 0.5) / n, (j + 0.5) / n), -1, &w).has_value();
            }
        return double(count) / (n * n) * (b.z - b.x) * (b.w - b.y);
    };
    const double at0 = passingArea(hexagon, 0.0);
    for (double degrees : {15.0, 30.0, 45.0, 90.0})
        CHECK(passingArea(hexagon, degrees * std::numbers::pi / 180.0) == Approx(at0).epsilon(0.01));
}

TEST_CASE("lens camera: cat's eyes: off axis the barrel cuts the pupil radially, and the bokeh's area is the "
          "passing rays' share of the bound", "[cpu][lens]") {
    const LensCamera cam = camera(shipped("dgauss-50mm.lens"), 5000.0, 0.0);
    // The passing rays' points in the rear plane (tests/support/lens_pupil.h).
    auto shape = [&](double r) {
        const test::PupilShape p = test::passingPupil(cam, r);
        return glm::dvec3(p.radial, p.tangential, p.area);
    };
    const glm::dvec3 centre = shape(0.0), edge = shape(0.95 * cam.filmRadius);
    std::printf("dgauss-50mm wide open: pupil at the centre %.3f x %.3f mm (sd), area %.1f mm^2; at the corner "
                "%.3f x %.3f, area %.1f\n", centre.x, centre.y, centre.z, edge.x, edge.y, edge.z);
    CHECK(centre.x == Approx(centre.y).epsilon(0.02));   // round on axis
    CHECK(edge.x < 0.8 * edge.y);                       // a cat's eye at the corner: narrow radially
    CHECK(edge.z < 0.8 * centre.z);                     // and smaller: optical vignetting
    // Stopped down to f/8 the barrel no longer cuts the bundle: the corner's pupil is round again.
    const LensCamera stopped = camera(shipped("dgauss-50mm.lens"), 5000.0, 8.0);
    double w = 0.0;
    int count = 0;
    for (int j = 0; j < 100; ++j)
        for (int i = 0; i < 100; ++i)
            count += lensCameraRay(stopped, glm::dvec2(0.5 * stopped.filmRadius, 0.0),
                                   glm::dvec2((i + 0.5) / 100.0, (j + 0.5) / 100.0), -1, &w).has_value();
    CHECK(count > 0);
}

TEST_CASE("lens camera: dispersion: a BK7 singlet's focal length changes by f / V from C to F, and red and blue "
          "defocus where green is sharp", "[cpu][lens]") {
    const LensSystem singlet = shipped("singlet-bk7-100mm.lens");
    // Cauchy's form through n_d with the Abbe number's n_F - n_C.
    const LensSurface& glass = singlet.surfaces[1];
    CHECK(indexAt(glass, kLineD) == glass.ior);
    CHECK((indexAt(glass, kLineF) - indexAt(glass, kLineC)) == Approx((glass.ior - 1.0) / glass.abbe).epsilon(1e-9));
    const double fC = -1.0 / paraxialMatrix(singlet, kLineC).c, fD = -1.0 / paraxialMatrix(singlet, kLineD).c,
                 fF = -1.0 / paraxialMatrix(singlet, kLineF).c;
    // Thin lens: f proportional to 1 / (n - 1), so f_C - f_F = f (n_F - n_C) / (n_d - 1) = f / V.
    CHECK(fC - fF == Approx(fD / glass.abbe).epsilon(0.02));
    CHECK(fC > fD);
    CHECK(fD > fF);
    // At f/16 the singlet's spherical aberration (as 1 / N^3) is small beside its chromatic
    // defocus (as 1 / N).
    const LensCamera cam = camera(singlet, 2000.0, 16.0);
    CHECK(cam.dispersion);
    const double green = rmsRadius(filmSpot(cam, 2000.0, kLineD)), red = rmsRadius(filmSpot(cam, 2000.0, kLineC)),
                 blue = rmsRadius(filmSpot(cam, 2000.0, kLineF));
    // Geometric optics per line: the point's image at the line's paraxial image distance, the
    // film where green's is: a disc of the exit pupil's diameter times the focus error over the
    // image's distance from the pupil (rms: diameter / (2 sqrt 2)). Red focuses behind the film,
    // blue in front of it. (Green's paraxial image, not the film: the autofocus put the film
    // where spherical aberration moves green's best focus, and it moves red's and blue's alike.)
    const double t = cam.lens.surfaces.back().thickness;
    const double s = 2000.0 - cam.lens.length() - t;
    auto imageAt = [&](double nm) {
        const LensMatrix m = paraxialMatrix(cam.lens, nm);
        return -(m.a * s + m.b) / (m.c * s + m.d);
    };
    const double imageD = imageAt(kLineD);
    auto predicted = [&](double nm, double* image) {
        *image = imageAt(nm);
        const glm::dvec2 pupil = exitPupil(cam.lens, cam.stopRadius);   // the stop is in front: its image by the lens
        return 2.0 * pupil.y * std::abs(*image - imageD) / (*image - pupil.x) / (2.0 * std::sqrt(2.0));
    };
    double imageC = 0.0, imageF = 0.0;
    const double expectC = predicted(kLineC, &imageC), expectF = predicted(kLineF, &imageF);
    std::printf("singlet-bk7-100mm at f/16 focused at 2 m: spot rms C %.4f mm (geometric optics %.4f), d %.4f mm, "
                "F %.4f mm (%.4f)\n", red, expectC, green, blue, expectF);
    CHECK(imageC > t);
    CHECK(imageF < t);
    CHECK(red == Approx(expectC).epsilon(0.1));
    CHECK(blue == Approx(expectF).epsilon(0.1));
    CHECK(red > 5.0 * green);
    CHECK(blue > 5.0 * green);
    // Without Abbe numbers there is nothing to disperse.
    CHECK_FALSE(camera(shipped("dgauss-50mm.lens"), 2000.0, 0.0).dispersion);
}
