// Lens prescriptions: the reader and the optics (renderer/lens.h says the conventions).
#include "renderer/lens.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <fstream>
#include <sstream>

namespace caustic {

int LensSystem::stopIndex() const {
    for (std::size_t i = 0; i < surfaces.size(); ++i)
        if (surfaces[i].stop) return int(i);
    return -1;
}

double LensSystem::length() const {
    double z = 0.0;
    for (std::size_t i = 0; i + 1 < surfaces.size(); ++i) z += surfaces[i].thickness;
    return z;
}

std::vector<double> surfaceVertices(const LensSystem& lens) {
    std::vector<double> z(lens.surfaces.size(), 0.0);
    for (std::size_t i = 1; i < z.size(); ++i) z[i] = z[i - 1] + lens.surfaces[i - 1].thickness;
    return z;
}

namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// Limits that keep every later computation finite: a lens is at most a metre long, its glasses'
// indices those of real glasses and crystals.
constexpr double kMaxLength = 1000.0;  // mm
constexpr double kMaxIor = 4.0;

}  // namespace

bool parseLensSystem(const std::string& text, const std::string& path, LensSystem* out, std::string* error) {
    LensSystem lens;
    lens.name = std::filesystem::path(path).stem().string();
    std::istringstream in(text);
    std::string line;
    int number = 0;
    auto fail = [&](const std::string& why) {
        *error = path + ":" + std::to_string(number) + ": " + why;
        return false;
    };
    while (std::getline(in, line)) {
        ++number;
        std::string body = line;
        if (const auto hash = body.find('#'); hash != std::string::npos) {
            const std::string comment = trim(body.substr(hash + 1));
            if (comment.rfind("name:", 0) == 0) lens.name = trim(comment.substr(5));
            if (comment.rfind("source:", 0) == 0) {
                if (!lens.source.empty()) lens.source += "; ";
                lens.source += trim(comment.substr(7));
            }
            body = body.substr(0, hash);
        }
        body = trim(body);
        if (body.empty()) continue;
        std::istringstream row(body);
        std::vector<double> values;
        std::string token;
        bool stop = false;
        while (row >> token) {
            if (token == "stop") {
                stop = true;
                continue;
            }
            char* end = nullptr;
            const double v = std::strtod(token.c_str(), &end);
            if (end == token.c_str() || *end != '\0') return fail("'" + token + "' is not a number");
            if (!std::isfinite(v)) return fail("'" + token + "' is not finite");
            values.push_back(v);
        }
        if (values.size() != 4 && values.size() != 5)
            return fail("expected radius, thickness, index, aperture diameter [and Abbe number]: 4 or 5 numbers, got " +
                        std::to_string(values.size()));
        LensSurface s;
        s.radius = values[0];
        s.thickness = values[1];
        s.ior = values[2];
        s.aperture = values[3];
        s.abbe = values.size() == 5 ? values[4] : 0.0;
        if (std::abs(s.radius) > 1e6) return fail("a radius beyond 1e6 mm (use 0 for a flat surface)");
        if (s.thickness < 0.0 || s.thickness > kMaxLength)
            return fail("thickness must be in [0, " + std::to_string(int(kMaxLength)) + "] mm");
        if (!(s.aperture > 0.0) || s.aperture > kMaxLength) return fail("aperture diameter must be in (0, 1000] mm");
        if (s.abbe < 0.0 || s.abbe > 200.0) return fail("Abbe number must be in [0, 200] (0: no dispersion)");
        if (s.ior == 0.0) {
            // pbrt's mark: air, and with radius 0 the aperture stop.
            s.ior = 1.0;
            if (s.radius == 0.0) stop = true;
        }
        if (s.ior < 1.0 || s.ior > kMaxIor) return fail("index must be 0 (air), or in [1, 4]");
        if (stop && s.radius != 0.0) return fail("the aperture stop must be flat (radius 0)");
        if (s.radius != 0.0 && s.aperture > 2.0 * std::abs(s.radius))
            return fail("aperture diameter larger than the surface's sphere (2 |radius|)");
        s.stop = stop;
        if (stop && lens.stopIndex() >= 0) return fail("a second aperture stop");
        lens.surfaces.push_back(s);
    }
    if (lens.surfaces.size() < 2) {
        *error = path + ": a lens needs at least two surfaces, found " + std::to_string(lens.surfaces.size());
        return false;
    }
    if (lens.length() > kMaxLength) {
        *error = path + ": the lens is longer than 1000 mm";
        return false;
    }
    *out = std::move(lens);
    return true;
}

bool readLensFile(const std::string& path, LensSystem* out, std::string* error) {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        *error = path + ": cannot open the lens file";
        return false;
    }
    std::stringstream text;
    text << f.rdbuf();
    if (text.str().size() > (1u << 20)) {
        *error = path + ": a lens file is at most 1 MiB";
        return false;
    }
    return parseLensSystem(text.str(), path, out, error);
}

namespace {

// A paraxial ray (height y, reduced angle nu = n u) from the air in front of the first vertex to
// the air behind the last (the y-nu method), at wavelength nm: its height and angle there, and its
// height at the stop's plane in *atStop (where given).
glm::dvec2 traceParaxial(const LensSystem& lens, double nm, double y, double nu, double* atStop = nullptr) {
    double n = 1.0;
    const std::size_t last = lens.surfaces.size() - 1;
    for (std::size_t i = 0; i <= last; ++i) {
        const LensSurface& s = lens.surfaces[i];
        if (s.stop && atStop) *atStop = y;
        const double n2 = indexAt(s, nm);
        nu -= y * (n2 - n) * (s.radius == 0.0 ? 0.0 : 1.0 / s.radius);
        n = n2;
        if (i < last) y += s.thickness * nu / n;
    }
    return {y, nu / n};
}

}  // namespace

std::optional<ParaxialLens> paraxialAnalysis(const LensSystem& lens) {
    // The matrix's first column is the ray parallel to the axis at height 1.
    const LensMatrix m = paraxialMatrix(lens);
    if (!(std::abs(m.c) > 1e-12)) return std::nullopt;  // afocal
    ParaxialLens p;
    p.efl = -1.0 / m.c;
    p.bfd = -m.a / m.c;
    p.ffd = -m.d / m.c;
    double yStop = 0.0;
    traceParaxial(lens, kLineD, 1.0, 0.0, &yStop);
    const int stop = lens.stopIndex();
    if (stop >= 0 && std::abs(yStop) > 1e-12) {
        p.entrancePupilDiameter = lens.surfaces[std::size_t(stop)].aperture / std::abs(yStop);
        p.fNumber = p.efl / p.entrancePupilDiameter;
    }
    return p;
}

double indexAt(const LensSurface& s, double nm) {
    if (s.ior == 1.0 || s.abbe <= 0.0 || nm == kLineD) return s.ior;
    // n = A + B / lambda^2 with n(d) = n_d and n(F) - n(C) = (n_d - 1) / V_d.
    const double b = (s.ior - 1.0) / s.abbe / (1.0 / (kLineF * kLineF) - 1.0 / (kLineC * kLineC));
    return s.ior + b * (1.0 / (nm * nm) - 1.0 / (kLineD * kLineD));
}

LensMatrix paraxialMatrix(const LensSystem& lens, double nm) {
    // The rays (1, 0) and (0, 1) give the matrix's columns.
    const glm::dvec2 first = traceParaxial(lens, nm, 1.0, 0.0), second = traceParaxial(lens, nm, 0.0, 1.0);
    return {first.x, second.x, first.y, second.y};
}

namespace {

// The aperture stop's shape where a camera stops it down: a circle, or a regular polygon in it.
struct StopShape {
    double radius = 0.0;
    int blades = 0;
    double rotation = 0.0;
    const ApertureMask* mask = nullptr;
};

// The fraction of a ray at (x, y) that passes the stop.
double stopTransmission(const StopShape& stop, double x, double y) {
    const double rho2 = x * x + y * y;
    if (rho2 > stop.radius * stop.radius) return 0.0;
    if (stop.mask && stop.mask->width > 0) return stop.mask->at(x / stop.radius, y / stop.radius);
    if (stop.blades < 3) return 1.0;
    // The polygon's edge facing the point: its midpoint's direction and distance R cos(pi / n).
    const double sector = 2.0 * std::numbers::pi / stop.blades;
    const double phi = std::atan2(y, x) - stop.rotation;
    const double k = std::floor(phi / sector);
    const double mid = stop.rotation + (k + 0.5) * sector;
    return x * std::cos(mid) + y * std::sin(mid) <= stop.radius * std::cos(0.5 * sector) ? 1.0 : 0.0;
}

bool refract(const glm::dvec3& d, glm::dvec3 n, double n1, double n2, glm::dvec3* out) {
    double cosI = -glm::dot(n, d);
    if (cosI < 0.0) {
        n = -n;
        cosI = -cosI;
    }
    const double eta = n1 / n2;
    const double k = 1.0 - eta * eta * (1.0 - cosI * cosI);
    if (k < 0.0) return false;
    *out = glm::normalize(eta * d + (eta * cosI - std::sqrt(k)) * n);
    return true;
}

// Where the ray meets the surface whose vertex is at z (the half of the sphere towards its
// vertex), and its normal there; false when it misses.
bool intersect(const LensSurface& s, double z, const LensRay& r, glm::dvec3* p, glm::dvec3* normal) {
    if (s.radius == 0.0) {
        if (std::abs(r.d.z) < 1e-15) return false;
        const double t = (z - r.o.z) / r.d.z;
        if (t <= 0.0) return false;
        *p = r.o + t * r.d;
        *normal = glm::dvec3(0.0, 0.0, 1.0);
        return true;
    }
    const glm::dvec3 centre(0.0, 0.0, z + s.radius);
    const glm::dvec3 oc = r.o - centre;
    const double b = glm::dot(oc, r.d), c = glm::dot(oc, oc) - s.radius * s.radius;
    const double disc = b * b - c;
    if (disc < 0.0) return false;
    const double root = std::sqrt(disc);
    double t = -1.0;
    for (const double ti : {-b - root, -b + root}) {
        if (ti <= 1e-12) continue;
        const double pz = r.o.z + ti * r.d.z;
        if ((pz - centre.z) * s.radius <= 0.0) {
            t = ti;
            break;
        }
    }
    if (t < 0.0) return false;
    *p = r.o + t * r.d;
    *normal = glm::normalize(*p - centre);
    return true;
}

// Through every surface, front to back (fromFilm false) or back to front; the stop's opening is
// `stop`'s where given, else its clear aperture.
std::optional<LensRay> trace(const LensSystem& lens, const std::vector<double>& z, LensRay r, double nm, bool fromFilm,
                             const StopShape* stop, double* pass = nullptr) {
    if (pass) *pass = 1.0;
    const std::size_t n = lens.surfaces.size();
    for (std::size_t step = 0; step < n; ++step) {
        const std::size_t k = fromFilm ? n - 1 - step : step;
        const LensSurface& s = lens.surfaces[k];
        glm::dvec3 p, normal;
        if (!intersect(s, z[k], r, &p, &normal)) return std::nullopt;
        if (s.stop && stop) {
            const double t = stopTransmission(*stop, p.x, p.y);
            if (!(t > 0.0)) return std::nullopt;
            if (pass) *pass = t;
        } else if (p.x * p.x + p.y * p.y > 0.25 * s.aperture * s.aperture) {
            return std::nullopt;
        }
        // The media on either side: behind surface k is its own, in front the one before's.
        const double behind = indexAt(s, nm), before = k > 0 ? indexAt(lens.surfaces[k - 1], nm) : 1.0;
        const double n1 = fromFilm ? behind : before, n2 = fromFilm ? before : behind;
        glm::dvec3 d = r.d;
        if (n1 != n2 && !refract(r.d, normal, n1, n2, &d)) return std::nullopt;
        r = {p, d};
    }
    return r;
}

double wavelengthOf(int channel) { return channel == 0 ? kLineC : channel == 2 ? kLineF : kLineD; }

}  // namespace

double ApertureMask::at(double x, double y) const {
    if (width <= 0 || std::abs(x) > 1.0 || std::abs(y) > 1.0) return 0.0;
    const int i = std::min(int((x * 0.5 + 0.5) * width), width - 1);
    const int j = std::min(int((0.5 - y * 0.5) * height), height - 1);
    return values[std::size_t(j) * std::size_t(width) + std::size_t(i)];
}

std::optional<LensRay> traceFromScene(const LensSystem& lens, LensRay r, double nm) {
    return trace(lens, surfaceVertices(lens), r, nm, false, nullptr);
}

std::optional<LensRay> traceFromFilm(const LensSystem& lens, LensRay r, double nm) {
    return trace(lens, surfaceVertices(lens), r, nm, true, nullptr);
}

std::optional<LensRay> lensCameraRay(const LensCamera& cam, glm::dvec2 film, glm::dvec2 u, int channel,
                                     double* weight) {
    *weight = 0.0;
    const double r = glm::length(film);
    const int bin = std::min(int(r / cam.filmRadius * kLensPupilBins), kLensPupilBins - 1);
    const glm::dvec4 b = cam.pupilBounds[std::size_t(bin)];
    if (b.x > b.z) return std::nullopt;
    const glm::dvec2 q(b.x + u.x * (b.z - b.x), b.y + u.y * (b.w - b.y));
    // The bounds are for film points on +x; turn the sample with the film point.
    const glm::dvec2 dir = r > 0.0 ? film / r : glm::dvec2(1.0, 0.0);
    const glm::dvec2 rear(q.x * dir.x - q.y * dir.y, q.x * dir.y + q.y * dir.x);
    const double rearZ = cam.vertexZ.back();
    const glm::dvec3 o(film, cam.filmZ);
    const glm::dvec3 d = glm::normalize(glm::dvec3(rear, rearZ) - o);
    const StopShape stop{cam.stopRadius, cam.blades, cam.bladeRotation, &cam.aperture};
    double pass = 1.0;
    const auto out = trace(cam.lens, cam.vertexZ, {o, d}, wavelengthOf(channel), true, &stop, &pass);
    if (!out) return std::nullopt;
    const double cosTheta = std::abs(d.z), dz = cam.filmZ - rearZ;
    const double area = (b.z - b.x) * (b.w - b.y);
    *weight = pass * cosTheta * cosTheta * cosTheta * cosTheta * area / (dz * dz) * cam.weightScale;
    return out;
}

namespace {

// The grid over the rear vertex's plane the exit-pupil bounds are found with: kPupilGrid x
// kPupilGrid points over the square of half side `extent`.
constexpr int kPupilGrid = 48;

// The box (x0, y0, x1, y1) of the grid points whose rays from the film point at radius r on +x
// pass (at any of `channels`' lines; empty: x0 > x1). The stop counts as its whole circle: the
// bounds are found on +x and turned with the film point, and a polygon or an aperture image is
// not symmetric under that turn (a hexagon's box from +x is cos 30 degrees too short across it at
// 30 degrees); the circle holds either at any angle. The lens and the circle are symmetric about
// y = 0, so the upper half of the grid is traced and mirrored.
glm::dvec4 pupilBox(const LensCamera& cam, double r, double extent, const std::vector<int>& channels) {
    const double cell = 2.0 * extent / kPupilGrid;
    glm::dvec4 box(1e30, 1e30, -1e30, -1e30);
    const StopShape stop{cam.stopRadius, 0, 0.0, nullptr};
    const glm::dvec3 o(r, 0.0, cam.filmZ);
    for (int j = kPupilGrid / 2; j < kPupilGrid; ++j)
        for (int i = 0; i < kPupilGrid; ++i) {
            const glm::dvec3 p(-extent + (i + 0.5) * cell, -extent + (j + 0.5) * cell, cam.vertexZ.back());
            const LensRay ray{o, glm::normalize(p - o)};
            bool passes = false;
            for (int c : channels) passes = passes || trace(cam.lens, cam.vertexZ, ray, wavelengthOf(c), true, &stop);
            if (passes) box = glm::dvec4(std::min(box.x, p.x), std::min(box.y, -p.y), std::max(box.z, p.x), std::max(box.w, p.y));
        }
    return box;
}

// The rms radius, on a film `film` mm behind the last vertex, of the real rays (at d) from the
// axial point `distance` mm in front of the film: a grid over the first surface finds the box of
// those that pass, a finer one in that box gives the spot.
double spotRadius(const LensSystem& lens, double film, double distance) {
    LensSystem l = lens;
    l.surfaces.back().thickness = film;
    const std::vector<double> z = surfaceVertices(l);
    const double filmZ = z.back() + film;
    const glm::dvec3 object(0.0, 0.0, filmZ - distance);
    const double r = 0.5 * l.surfaces.front().aperture;
    glm::dvec4 box(-r, -r, r, r);
    for (int pass = 0; pass < 2; ++pass) {
        const int n = pass == 0 ? 48 : 16;
        glm::dvec2 sum(0.0);
        double sq = 0.0;
        int count = 0;
        glm::dvec4 found(1e30, 1e30, -1e30, -1e30);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const glm::dvec3 target(box.x + (box.z - box.x) * (i + 0.5) / n, box.y + (box.w - box.y) * (j + 0.5) / n, 0.0);
                const auto out = trace(l, z, {object, glm::normalize(target - object)}, kLineD, false, nullptr);
                if (!out) continue;
                found = glm::dvec4(std::min(found.x, target.x), std::min(found.y, target.y), std::max(found.z, target.x),
                                   std::max(found.w, target.y));
                const double t = (filmZ - out->o.z) / out->d.z;
                const glm::dvec2 hit(out->o.x + t * out->d.x, out->o.y + t * out->d.y);
                sum += hit;
                sq += glm::dot(hit, hit);
                ++count;
            }
        if (count < 4) return 1e30;
        if (pass == 0) {
            const double cell = 2.0 * r / n;
            box = found + glm::dvec4(-cell, -cell, cell, cell);
            continue;
        }
        const glm::dvec2 mean = sum / double(count);
        return std::sqrt(std::max(sq / count - glm::dot(mean, mean), 0.0));
    }
    return 1e30;
}

std::string millimetres(double v) {
    char text[64];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

}  // namespace

bool prepareLensCamera(const LensSystem& lens, const LensCameraSettings& settings, LensCamera* out, std::string* error) {
    LensCamera cam;
    cam.lens = lens;
    const int stop = lens.stopIndex();
    if (stop < 0) {
        *error = "the lens has no aperture stop (a flat row of index 0, or one marked 'stop')";
        return false;
    }
    if (lens.surfaces.size() > std::size_t(kLensMaxSurfaces)) {
        *error = "the lens has " + std::to_string(lens.surfaces.size()) + " surfaces; a camera takes at most " +
                 std::to_string(kLensMaxSurfaces);
        return false;
    }
    if (lens.surfaces.back().ior != 1.0) {
        *error = "the last surface must be followed by air (the film is in air)";
        return false;
    }
    const auto paraxial = paraxialAnalysis(lens);
    if (!paraxial || !(paraxial->efl > 0.0) || !(paraxial->fNumber > 0.0)) {
        *error = "the lens does not form a real image (afocal or diverging: no positive focal length)";
        return false;
    }
    cam.efl = paraxial->efl;
    cam.fNumberOpen = paraxial->fNumber;
    cam.fNumber = cam.fNumberOpen;
    const double openRadius = 0.5 * lens.surfaces[std::size_t(stop)].aperture;
    cam.stopRadius = openRadius;
    if (settings.fNumber > 0.0) {
        if (settings.fNumber < cam.fNumberOpen * (1.0 - 1e-9)) {
            cam.notes.push_back("f/" + millimetres(settings.fNumber) + " is wider than the lens opens; using f/" +
                                millimetres(cam.fNumberOpen));
        } else {
            // The entrance pupil is the stop's paraxial image: its diameter, and so 1 / N, scales with the stop's.
            cam.fNumber = settings.fNumber;
            cam.stopRadius = openRadius * cam.fNumberOpen / settings.fNumber;
        }
    }
    cam.lens.surfaces[std::size_t(stop)].aperture = 2.0 * cam.stopRadius;
    cam.blades = settings.blades >= 3 ? settings.blades : 0;
    cam.aperture = settings.aperture;
    cam.bladeRotation = settings.bladeRotation;
    // Focus (thick lens, by moving the whole lens): the film at distance t behind the last vertex
    // sees sharp the axial point D in front of the film, D - L - t in front of the first vertex.
    // With the matrix from vertex to vertex, t = -(a s + b) / (c s + d), s = D - L - t:
    // c t^2 - (c K + d - a) t - (a K + b) = 0, K = D - L; the root nearer the infinity focus -a / c.
    const LensMatrix m = paraxialMatrix(lens);
    const double length = lens.length();
    const double infinity = -m.a / m.c;
    const double K = settings.focusDistanceMm - length;
    const double qa = m.c, qb = -(m.c * K + m.d - m.a), qc = -(m.a * K + m.b);
    const double disc = qb * qb - 4.0 * qa * qc;
    double t = infinity;
    bool tooNear = false;
    if (!(settings.focusDistanceMm < 1e12)) {
        t = infinity;
    } else if (disc < 0.0 || K <= 0.0) {
        // Nearer than the lens can focus: its closest focus, the K where the two roots meet (the
        // discriminant, a quadratic in K: c^2 K^2 + (2 c (d - a) + 4 a c) K + (d - a)^2 + 4 b c = 0,
        // its larger root), and there t = (c K + d - a) / (2 c).
        const double ka = m.c * m.c, kb = 2.0 * m.c * (m.d - m.a) + 4.0 * m.a * m.c,
                     kc = (m.d - m.a) * (m.d - m.a) + 4.0 * m.b * m.c;
        const double kd = std::max(kb * kb - 4.0 * ka * kc, 0.0);
        const double closest = (-kb + std::sqrt(kd)) / (2.0 * ka);
        t = (m.c * closest + m.d - m.a) / (2.0 * m.c);
        tooNear = true;
    } else {
        const double root = std::sqrt(disc);
        const double t0 = (-qb - root) / (2.0 * qa), t1 = (-qb + root) / (2.0 * qa);
        t = std::abs(t0 - infinity) < std::abs(t1 - infinity) ? t0 : t1;
    }
    if (!(t > 0.0) || !std::isfinite(t)) {
        *error = "cannot focus the lens at " + millimetres(settings.focusDistanceMm) + " mm";
        return false;
    }
    // Then as an autofocus would: the film where real rays from the point (at d, through the
    // stop as set) make the smallest spot, within 3 % of the paraxial focus (spherical
    // aberration moves the best focus towards the lens).
    if (!tooNear && settings.focusDistanceMm < 1e12) {
        auto spot = [&](double film) { return spotRadius(cam.lens, film, settings.focusDistanceMm); };
        double lo = 0.97 * t, hi = 1.03 * t;
        const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
        double x1 = hi - golden * (hi - lo), x2 = lo + golden * (hi - lo);
        double f1 = spot(x1), f2 = spot(x2);
        for (int k = 0; k < 32; ++k) {   // the bracket shrinks to 6 % x 0.618^32, 1e-8 of the distance
            if (f1 < f2) {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - golden * (hi - lo);
                f1 = spot(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + golden * (hi - lo);
                f2 = spot(x2);
            }
        }
        const double best = 0.5 * (lo + hi);
        if (std::isfinite(best) && spot(best) < spot(t)) t = best;
    }
    cam.lens.surfaces.back().thickness = t;
    cam.vertexZ = surfaceVertices(cam.lens);
    cam.filmZ = cam.vertexZ.back() + t;
    // The focus reached: the requested distance, or (nearer than the lens focuses) the film's
    // paraxial conjugate, s = -(b + d t) / (a + c t) in front of the first vertex.
    const double s = -(m.b + m.d * t) / (m.a + m.c * t);
    cam.focusDistanceMm = tooNear ? s + length + t : settings.focusDistanceMm;
    if (tooNear)
        cam.notes.push_back("a focus distance of " + millimetres(settings.focusDistanceMm) +
                            " mm is nearer than the lens focuses; focused at its closest, " +
                            millimetres(cam.focusDistanceMm) + " mm");
    cam.filmHalfWidth = 0.5 * settings.filmWidthMm;
    cam.filmHalfHeight = 0.5 * settings.filmHeightMm;
    cam.filmRadius = std::hypot(cam.filmHalfWidth, cam.filmHalfHeight);
    bool anyAbbe = false;
    for (const LensSurface& surface : lens.surfaces) anyAbbe = anyAbbe || (surface.ior != 1.0 && surface.abbe > 0.0);
    cam.dispersion = settings.dispersion && anyAbbe;
    const std::vector<int> channels = cam.dispersion ? std::vector<int>{0, 1, 2} : std::vector<int>{1};
    // The pupil bounds: the rear element's clear aperture, half as large again, holds every ray
    // that can pass (the rear element is the last thing a film ray crosses, whatever its angle).
    // Each bin's box: the union of the boxes at its two ends and its middle (the ends shared
    // with the neighbours), grown by one grid cell.
    const double extent = 0.75 * lens.surfaces.back().aperture;
    std::vector<glm::dvec4> boxes(2 * kLensPupilBins + 1);
    for (std::size_t k = 0; k < boxes.size(); ++k)
        boxes[k] = pupilBox(cam, cam.filmRadius * double(k) / (2.0 * kLensPupilBins), extent, channels);
    const double cell = 2.0 * extent / kPupilGrid;
    cam.pupilBounds.resize(kLensPupilBins);
    for (std::size_t i = 0; i < std::size_t(kLensPupilBins); ++i) {
        glm::dvec4 box = boxes[2 * i];
        for (std::size_t k = 2 * i + 1; k <= 2 * i + 2; ++k)
            box = glm::dvec4(glm::min(glm::dvec2(box), glm::dvec2(boxes[k])), glm::max(glm::dvec2(box.z, box.w), glm::dvec2(boxes[k].z, boxes[k].w)));
        cam.pupilBounds[i] = box.x > box.z ? box : box + glm::dvec4(-cell, -cell, cell, cell);
    }
    // Exposure: the mean weight at the film's centre is 1 (over the traced wavelengths).
    cam.weightScale = 1.0;
    double sum = 0.0;
    constexpr int kAxis = 64;
    for (int c : channels)
        for (int j = 0; j < kAxis; ++j)
            for (int i = 0; i < kAxis; ++i) {
                double w = 0.0;
                lensCameraRay(cam, glm::dvec2(0.0), glm::dvec2((i + 0.5) / kAxis, (j + 0.5) / kAxis), c, &w);
                sum += w;
            }
    const double mean = sum / (double(kAxis) * kAxis * double(channels.size()));
    if (!(mean > 0.0)) {
        *error = "no ray from the film's centre passes the lens";
        return false;
    }
    cam.weightScale = 1.0 / mean;
    *out = std::move(cam);
    return true;
}

double lensPassFraction(const LensCamera& cam, int n) {
    std::size_t passed = 0, total = 0;
    for (int fy = 0; fy < n; ++fy)
        for (int fx = 0; fx < n; ++fx) {
            const glm::dvec2 film(cam.filmHalfWidth * (2.0 * (fx + 0.5) / n - 1.0),
                                  cam.filmHalfHeight * (2.0 * (fy + 0.5) / n - 1.0));
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    double w = 0.0;
                    passed += lensCameraRay(cam, film, glm::dvec2((i + 0.5) / n, (j + 0.5) / n), -1, &w).has_value();
                    ++total;
                }
        }
    return double(passed) / double(total);
}

std::vector<glm::vec4> lensUniformBlock(const LensCamera& cam) {
    std::vector<glm::vec4> block(kLensBlockRows, glm::vec4(0.0f));
    const std::size_t n = cam.lens.surfaces.size();
    block[0] = glm::vec4(float(n), float(cam.filmZ), float(cam.filmRadius), float(cam.weightScale));
    block[1] = glm::vec4(float(cam.filmHalfWidth), float(cam.filmHalfHeight), float(cam.vertexZ.back()),
                         float(cam.stopRadius));
    block[2] = glm::vec4(float(cam.blades), float(cam.bladeRotation), cam.dispersion ? 1.0f : 0.0f, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
        const LensSurface& s = cam.lens.surfaces[i];
        block[3 + 2 * i] = glm::vec4(float(s.radius), float(cam.vertexZ[i]), float(0.5 * s.aperture), s.stop ? 1.0f : 0.0f);
        block[4 + 2 * i] = glm::vec4(float(indexAt(s, kLineC)), float(indexAt(s, kLineD)), float(indexAt(s, kLineF)), 0.0f);
    }
    for (int i = 0; i < kLensPupilBins; ++i)
        block[std::size_t(3 + 2 * kLensMaxSurfaces + i)] = glm::vec4(cam.pupilBounds[std::size_t(i)]);
    return block;
}

}  // namespace caustic
