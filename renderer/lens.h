// Lens prescriptions (issue 42, "Bokeh lookdev with real lenses"): the file format, its reader,
// and the lens system's optics on the CPU in double precision (paraxial analysis, real rays),
// which the camera's setup and the tests use. docs/lenses.md describes the format and the shipped
// designs (assets/lenses/).
//
// Conventions: lengths in millimetres; the optical axis is z, the scene at z < 0 in front of the
// first surface, the film behind the last. Surfaces are listed from the scene side to the film
// side (as pbrt's and Kolb et al.'s tables are). A surface's radius is signed: > 0 when its centre
// of curvature lies behind it (towards the film), 0 for a flat surface. Its thickness is the axial
// distance to the next surface (for the last one: to the film, which focusing sets). Its index is
// that of the medium behind it (towards the film); 1 (or 0, pbrt's mark) is air. The aperture stop
// is the surface of radius 0 whose index is 0 (pbrt's convention) or the row marked `stop`.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace caustic {

struct LensSurface {
    double radius = 0.0;     // mm, signed (see above); 0: flat
    double thickness = 0.0;  // mm to the next surface (the last: to the film)
    double ior = 1.0;        // n_d of the medium behind it; 1: air
    double abbe = 0.0;       // V_d of that medium; 0: no dispersion given
    double aperture = 0.0;   // clear diameter, mm
    bool stop = false;       // the aperture stop
};

struct LensSystem {
    std::string name;     // from a "# name:" line, else the file's stem
    std::string source;   // from "# source:" lines: where the design is published
    std::vector<LensSurface> surfaces;
    int stopIndex() const;  // the aperture stop's index, -1 without one
    double length() const;  // axial distance from the first surface to the last (mm)
};

// Reads a prescription (the format of docs/lenses.md). On error returns false with a message that
// names `path` and the line ("dgauss.lens:7: expected 4 or 5 numbers, got 3").
bool parseLensSystem(const std::string& text, const std::string& path, LensSystem* out, std::string* error);
bool readLensFile(const std::string& path, LensSystem* out, std::string* error);

// Paraxial (first-order) properties, from a paraxial ray traced through the surfaces (the y-nu
// method): effective focal length, back focal distance (last surface to the rear focal point),
// front focal distance (first vertex to the front focal point), the entrance pupil's diameter and the f-number EFL / entrance pupil.
struct ParaxialLens {
    double efl = 0.0;
    double bfd = 0.0;
    double ffd = 0.0;
    double entrancePupilDiameter = 0.0;
    double fNumber = 0.0;
};
std::optional<ParaxialLens> paraxialAnalysis(const LensSystem& lens);

// The Fraunhofer lines (nm) that n_d and V_d are defined at. A lens camera with dispersion traces
// its red, green and blue rays at C, d and F (docs/lenses.md, "Dispersion").
inline constexpr double kLineC = 656.2725, kLineD = 587.5618, kLineF = 486.1327;
// The index at wavelength `nm` of the medium behind `s`: n_d without an Abbe number; with one, the
// two-term Cauchy form n = A + B / lambda^2 through n_d whose n_F - n_C is (n_d - 1) / V_d (the
// Abbe number's definition). Air stays 1.
double indexAt(const LensSurface& s, double nm);

// The paraxial ray-transfer matrix from the air in front of the first vertex to the air behind
// the last: (y, u) -> (a y + b u, c y + d u), u the ray's angle, at wavelength `nm`.
struct LensMatrix {
    double a = 1.0, b = 0.0, c = 0.0, d = 1.0;
};
LensMatrix paraxialMatrix(const LensSystem& lens, double nm = kLineD);

// A real ray through the system in double precision: origin and unit direction, in the lens's
// frame. traceFromScene starts in front of the first surface (z below its vertex) and returns the
// ray behind the last surface; traceFromFilm the reverse. Empty when the ray misses a surface,
// meets one outside its clear aperture, or is totally internally reflected. `nm`: the
// wavelength the glasses' indices are taken at (indexAt).
struct LensRay {
    glm::dvec3 o, d;
};
std::optional<LensRay> traceFromScene(const LensSystem& lens, LensRay r, double nm = kLineD);
std::optional<LensRay> traceFromFilm(const LensSystem& lens, LensRay r, double nm = kLineD);

// A lens system as a camera (docs/lenses.md, "The lens camera"): focused by moving the whole lens
// (the last thickness becomes the film's distance), stopped down, and with the bounds of its exit
// pupil per film radius, so that the camera's rays aim only where they can pass.
// An aperture image's transmission over the square around the stop's circle (row 0 at the top,
// +y up), as renderer/gpu_scene.h's ApertureImage holds it.
struct ApertureMask {
    int width = 0, height = 0;
    std::vector<float> values;  // width x height, in [0, 1]
    // The nearest texel's value at p in [-1, 1]^2 (0 outside).
    double at(double x, double y) const;
};

struct LensCameraSettings {
    double focusDistanceMm = 1e9;  // of the plane of focus, from the film along the axis
    double fNumber = 0.0;          // 0: wide open; wider than the lens allows: wide open
    double filmWidthMm = 36.0, filmHeightMm = 24.0;
    int blades = 0;                // 0: the stop is round; >= 3: a regular polygon in its circle
    double bladeRotation = 0.0;    // radians; 0: a vertex along the lens's +x
    bool dispersion = true;        // trace each channel at its own wavelength (where a glass has an Abbe number)
    ApertureMask aperture;         // width 0: none; else it shapes the stop instead of the blades
};

// Film radii binned for the exit-pupil bounds (the GPU's table has as many).
inline constexpr int kLensPupilBins = 64;
inline constexpr int kLensMaxSurfaces = 32;
// The shader's lens block: 3 rows of constants, 2 per surface, 1 per pupil bin (vec4s).
inline constexpr int kLensBlockRows = 3 + 2 * kLensMaxSurfaces + kLensPupilBins;

struct LensCamera {
    LensSystem lens;                 // as focused and stopped down
    std::vector<double> vertexZ;     // surfaceVertices(lens)
    double filmZ = 0.0;              // the film's z (the last vertex + the last thickness)
    double filmHalfWidth = 0.0, filmHalfHeight = 0.0, filmRadius = 0.0;  // mm; radius: half the diagonal
    double stopRadius = 0.0;         // the stop's radius as stopped down (a polygon: its circumcircle)
    int blades = 0;
    double bladeRotation = 0.0;
    ApertureMask aperture;           // the stop's transmission (width 0: none)
    bool dispersion = false;         // asked for, and some glass has an Abbe number
    double efl = 0.0;                // paraxial, at d
    double fNumber = 0.0;            // as stopped down (paraxial, at infinity focus)
    double fNumberOpen = 0.0;        // wide open
    double focusDistanceMm = 0.0;    // what it focuses at (its closest focus where asked nearer)
    // Per bin of film radius [i, i + 1) filmRadius / bins: the box (x0, y0, x1, y1) in the plane of
    // the rear vertex through which rays from film points on the +x axis at those radii can pass
    // (at any of the traced wavelengths, through the stop's whole circle: blades and an aperture
    // image are not symmetric under the turn to other film angles); empty (x0 > x1) where none passes.
    std::vector<glm::dvec4> pupilBounds;
    double weightScale = 1.0;        // makes the mean weight at the film's centre 1
    std::vector<std::string> notes;  // what was adjusted (a focus nearer than the closest, an f-number wider than open)
};

bool prepareLensCamera(const LensSystem& lens, const LensCameraSettings& settings, LensCamera* out, std::string* error);

// The camera ray from film point `film` (mm, in the lens's x, y) through the pupil sample u in
// [0, 1)^2, at the wavelength of `channel` (0, 1, 2: C, d, F; -1: d): the ray in front of the lens
// and its weight, cos^4(theta) A / z^2 times weightScale (A the bound's area, z the film's
// distance from the rear vertex's plane, theta the ray's angle with the axis at the film); empty
// when the lens blocks it. The shader's lensCameraRay (integrator/lens_camera.glsl) is this in float.
std::optional<LensRay> lensCameraRay(const LensCamera& camera, glm::dvec2 film, glm::dvec2 u, int channel,
                                     double* weight);

// The fraction of camera rays that pass, over `n` x `n` film points spread over the film and as
// many pupil samples each (at d).
double lensPassFraction(const LensCamera& camera, int n = 16);

// The lens block the shader reads (integrator/lens_camera.glsl, LensBlock): kLensBlockRows vec4s.
std::vector<glm::vec4> lensUniformBlock(const LensCamera& camera);

// The z of each surface's vertex, the first at 0.
std::vector<double> surfaceVertices(const LensSystem& lens);

}  // namespace caustic
