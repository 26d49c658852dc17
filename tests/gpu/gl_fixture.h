// The GL context every GPU test uses: one headless context per test process, created on first
// use with debug output on. A test that cannot get a context FAILS (never skips).
#pragma once

#include "renderer/gl_context.h"
#include "renderer/renderer.h"
#include "renderer/scene.h"

#include <memory>
#include <string>

namespace caustic::test {

HeadlessGlContext& glContext();                  // REQUIREs a context
// The configuration the tests run with: the device's defaults (and the CAUSTIC_* variables, so
// that a run of the suite can be pointed at another configuration).
IntegratorConfig testConfig();
// REQUIREs the integrator to compile.
std::unique_ptr<Renderer> makeRenderer(const IntegratorConfig& config = testConfig());
// A test kernel from tests/gpu/kernels/ (compiled once per process; REQUIREs it to compile).
// Kernels include the integrator's own shader files, so they test the real code, compiled with
// testConfig()'s defines.
unsigned kernel(const std::string& name);
// Renders `samples` spp of `scene` (REQUIREs setScene to succeed) and returns the film.
Film renderFilm(Renderer& renderer, const Scene& scene, int samples);

// The analytic test scene: a camera inside a closed diffuse sphere (radius 2) of albedo a whose
// surface emits Le, so that every pixel sees L = Le / (1 - a). 16 x 16, max depth 100.
Scene closedEmittingSphere(glm::vec3 albedo, glm::vec3 emission);

// scenes/<file> at width x height pixels (REQUIREs that it loads).
Scene sceneFromFile(const std::string& file, int width, int height);

// scenes/cornell-box.json at size x size pixels (REQUIREs that it loads).
Scene cornellBox(int size);

// Whether `defines` holds the define `name`.
bool hasDefine(const ShaderDefines& defines, const char* name);

// A floor: the canonical quad turned to face +y, [-halfSize, halfSize]^2 at y = 0.
Object floorQuad(const std::string& material, float halfSize);
// A sphere of `radius` centred at `centre`.
Object sphereAt(const std::string& material, glm::vec3 centre, float radius);

// Mean over all pixels and its standard error (from the per-pixel variances), per channel.
struct ImageStats { glm::dvec3 mean{0.0}; glm::dvec3 standardError{0.0}; };
ImageStats imageStats(const Film& film);
// CHECKs that two renders of the same integral have the same image mean per channel, within k
// combined standard errors.
void checkSameMean(const Film& a, const Film& b, double k = 4.0);
// CHECKs that two renders of the same integral agree per block of a 4 x 4 grid and channel within
// 4 combined standard errors (48 comparisons), and the test's own power: the comparison must be
// tighter than a tenth of the blocks' values on average. The width and height must be multiples of 4.
void checkBlocksAgree(const Film& a, const Film& b, const char* what);

// The same scene by MIS, by light sampling alone (spp samples) and by BSDF sampling alone (4 spp
// samples: it is the noisier one), each pair checked by checkBlocksAgree; leaves the renderer on MIS.
void checkStrategiesAgree(Renderer& r, const Scene& s, int spp);

}  // namespace caustic::test
