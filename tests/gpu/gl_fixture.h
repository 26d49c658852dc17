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
std::unique_ptr<Renderer> makeRenderer();        // REQUIREs the integrator to compile
// A test kernel from tests/gpu/kernels/ (compiled once per process; REQUIREs it to compile).
// Kernels include the integrator's own shader files, so they test the real code.
unsigned kernel(const std::string& name);
// Renders `samples` spp of `scene` (REQUIREs setScene to succeed) and returns the film.
Film renderFilm(Renderer& renderer, const Scene& scene, int samples);

// Mean over all pixels and its standard error (from the per-pixel variances), per channel.
struct ImageStats { glm::dvec3 mean{0.0}; glm::dvec3 standardError{0.0}; };
ImageStats imageStats(const Film& film);

}  // namespace caustic::test
