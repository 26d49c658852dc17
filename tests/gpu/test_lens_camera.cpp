// The lens-system camera on the GPU (integrator/lens_camera.glsl) against its CPU twin
// (renderer/lens.h, lensCameraRay) and against the thin lens:
//   - the shader's rays in the lens's frame equal the CPU's (double) for the same film points,
//     pupil samples and wavelengths, with blades and dispersion, so what the CPU side computes
//     (focus, picking through the lens) is what renders;
//   - in the limit of one thin element (a 0.8 mm equiconvex lens of f = 200 mm, its stop at its
//     front) the image equals the thin-lens camera's at the same focus, aperture and field, within
//     noise, once the lens's natural vignetting (cos^4 of the chief ray's angle) is divided out;
//   - a lens file that cannot be read fails the scene with a message naming camera.lens and the file;
//   - the editor picks through the lens (editor::cameraRay with the renderer's lens system), and a
//     Shift+click focus there makes that pixel's rays meet on the picked point's plane.
#include "tests/gpu/gl_fixture.h"
#include "tests/support/lens_pupil.h"

#include "renderer/camera.h"
#include "editor/model/lookdev.h"
#include "editor/model/viewport_math.h"
#include "renderer/lens.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <vector>

using namespace caustic;

namespace {

std::string lensPath(const char* name) { return std::string(CAUSTIC_SOURCE_DIR) + "/assets/lenses/" + name; }

Scene lensScene(const std::string& lens, float fStop, int blades) {
    Scene s;
    s.render.width = 96;
    s.render.height = 64;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(0.0f)});
    s.objects.push_back(test::floorQuad("grey", 4.0f));
    s.objects.push_back(test::sphereAt("grey", glm::vec3(0.0f, 0.5f, -1.0f), 0.5f));
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(1.0f);
    s.camera.position = glm::vec3(0.0f, 0.6f, 2.0f);
    s.camera.lookAt = glm::vec3(0.0f, 0.5f, -1.0f);
    s.camera.lens = lens;
    s.camera.lensFStop = fStop;
    s.camera.blades = blades;
    s.camera.bladeRotationDegrees = 10.0f;
    return s;
}

struct GpuLensRay { glm::vec3 o; float weight; glm::vec3 d; bool passes; };

std::vector<GpuLensRay> traceOnGpu(Renderer& r, const std::vector<glm::vec4>& inputs) {
    const std::size_t n = inputs.size() / 2;
    GLuint buffers[2];
    glCreateBuffers(2, buffers);
    glNamedBufferData(buffers[0], GLsizeiptr(inputs.size() * sizeof(glm::vec4)), inputs.data(), GL_STATIC_DRAW);
    glNamedBufferData(buffers[1], GLsizeiptr(2 * n * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    const GLuint program = test::kernel("lens_rays.comp");
    r.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, buffers[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, buffers[1]);
    glUseProgram(program);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_count"), GLuint(n));
    glDispatchCompute(GLuint((n + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> out(2 * n);
    glGetNamedBufferSubData(buffers[1], 0, GLsizeiptr(out.size() * sizeof(glm::vec4)), out.data());
    glDeleteBuffers(2, buffers);
    REQUIRE(glDebugErrorCount() == 0);
    std::vector<GpuLensRay> rays;
    for (std::size_t i = 0; i < n; ++i)
        rays.push_back({glm::vec3(out[2 * i]), out[2 * i].w, glm::vec3(out[2 * i + 1]), out[2 * i + 1].w > 0.5f});
    return rays;
}

}  // namespace

TEST_CASE("lens camera: the shader's rays through a lens system are the CPU's", "[gpu][camera][lens]") {
    auto renderer = test::makeRenderer();
    struct Case { const char* file; float fStop; int blades; };
    for (const Case& k : {Case{"dgauss-50mm.lens", 2.8f, 6}, Case{"singlet-bk7-100mm.lens", 0.0f, 0},
                          Case{"fisheye-10mm.lens", 0.0f, 5}, Case{"telephoto-250mm.lens", 8.0f, 0}}) {
        INFO(k.file);
        const Scene s = lensScene(lensPath(k.file), k.fStop, k.blades);
        std::string error;
        REQUIRE(renderer->setScene(s, &error));
        const LensCamera* cam = renderer->lensCamera();
        REQUIRE(cam != nullptr);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        std::vector<glm::vec4> inputs;
        std::vector<glm::dvec2> films, us;
        std::vector<int> channels;
        for (int i = 0; i < 4000; ++i) {
            const glm::dvec2 film(cam->filmHalfWidth * (2.0 * uniform(rng) - 1.0), cam->filmHalfHeight * (2.0 * uniform(rng) - 1.0));
            const glm::dvec2 u(uniform(rng), uniform(rng));
            const int channel = cam->dispersion ? i % 3 : 1;
            films.push_back(film);
            us.push_back(u);
            channels.push_back(channel);
            inputs.push_back(glm::vec4(glm::vec2(film), glm::vec2(u)));
            inputs.push_back(glm::vec4(float(channel), 0.0f, 0.0f, 0.0f));
        }
        const std::vector<GpuLensRay> gpu = traceOnGpu(*renderer, inputs);
        int passed = 0, verdicts = 0, far = 0;
        double worstDir = 0.0, worstOrigin = 0.0, worstWeight = 0.0;
        for (std::size_t i = 0; i < gpu.size(); ++i) {
            double weight = 0.0;
            // The float inputs, as the GPU got them.
            const auto cpu = lensCameraRay(*cam, glm::dvec2(glm::vec2(films[i])), glm::dvec2(glm::vec2(us[i])), channels[i], &weight);
            if (cpu.has_value() != gpu[i].passes) {
                ++verdicts;
                continue;
            }
            if (!cpu) continue;
            ++passed;
            const double dd = glm::length(cpu->d - glm::dvec3(gpu[i].d));
            const double dO = glm::length(cpu->o - glm::dvec3(gpu[i].o));
            const double dw = std::abs(weight - gpu[i].weight) / weight;
            worstDir = std::max(worstDir, dd);
            worstOrigin = std::max(worstOrigin, dO);
            worstWeight = std::max(worstWeight, dw);
            far += dd > 1e-4 || dO > 5e-3 || dw > 1e-4;
        }
        std::printf("lens rays %-24s %d of %zu pass; GPU vs CPU: %d verdicts differ, worst direction %.2g, origin "
                    "%.2g mm, weight %.2g (relative)\n", k.file, passed, gpu.size(), verdicts, worstDir, worstOrigin,
                    worstWeight);
        CHECK(passed > 1000);
        // A ray grazing an aperture's edge may be decided differently in float.
        CHECK(verdicts <= 4);
        CHECK(far == 0);
    }
}

TEST_CASE("lens camera: one thin element renders the thin-lens camera's image", "[gpu][camera][lens]") {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "caustic-thin-element";
    std::filesystem::create_directories(dir);
    const std::string file = (dir / "thin.lens").string();
    {
        std::ofstream f(file);
        f << "# an equiconvex lens of f = 200 mm, 0.8 mm thick, its stop (20 mm: f/10) at its front\n"
             "0 0 0 20\n200 0.8 1.5 24\n-200 0 1 24\n";
    }
    const double focusMm = 2000.0;
    Scene lens = lensScene(file, 0.0f, 0);
    lens.render.width = 64;
    lens.render.height = 48;
    lens.render.maxDepth = 2;
    lens.camera.sensorWidthMm = 8.0f;
    lens.camera.focalDistance = float(focusMm / 1000.0);
    lens.objects.push_back(test::sphereAt("grey", glm::vec3(0.25f, 0.3f, 0.9f), 0.12f));  // near: blurred
    lens.objects.push_back(test::sphereAt("grey", glm::vec3(-0.6f, 0.6f, -3.0f), 0.4f));  // far: blurred
    auto renderer = test::makeRenderer();
    std::string error;
    REQUIRE(renderer->setScene(lens, &error));
    const LensCamera cam = *renderer->lensCamera();
    // The thin lens at the rear principal plane, v from the film: H' lies BFD - EFL behind the last
    // vertex, with EFL and BFD those of the focused system.
    const auto p = paraxialAnalysis(cam.lens);
    REQUIRE(p);
    const double v = cam.filmZ - (cam.vertexZ.back() + p->bfd - p->efl);
    Scene thin = lens;
    thin.camera.lens.clear();
    const glm::dvec3 forward = glm::normalize(glm::dvec3(lens.camera.lookAt) - glm::dvec3(lens.camera.position));
    thin.camera.position = glm::vec3(glm::dvec3(lens.camera.position) + forward * (v / 1000.0));
    thin.camera.lookAt = glm::vec3(glm::dvec3(thin.camera.position) + forward);
    thin.camera.focalDistance = float((focusMm - v) / 1000.0);
    thin.camera.apertureRadius = 0.010f;
    thin.camera.fovAxis = FovAxis::Y;
    thin.camera.fovDegrees = float(2.0 * std::atan(cam.filmHalfHeight / v) * 180.0 / std::numbers::pi);
    const int spp = 256;
    Film a = test::renderFilm(*renderer, lens, spp);
    const Film b = test::renderFilm(*renderer, thin, spp);
    // Divide out the lens's natural vignetting: cos^4 of the chief ray's angle at each pixel.
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const double fx = cam.filmHalfWidth * (2.0 * (x + 0.5) / a.width - 1.0);
            const double fy = cam.filmHalfHeight * (2.0 * (y + 0.5) / a.height - 1.0);
            const double c2 = v * v / (v * v + fx * fx + fy * fy);
            const float k = float(1.0 / (c2 * c2));
            a.mean[a.index(x, y)] *= k;
            a.varianceOfMean[a.index(x, y)] *= k * k;
        }
    test::checkSameMean(a, b);
    test::checkBlocksAgree(a, b, "thin element vs thin lens");
    // And the images are not flat: the blur matters to the comparison.
    const test::ImageStats sa = test::imageStats(a);
    CHECK(sa.mean.x > 0.2);
    std::filesystem::remove_all(dir);
}

TEST_CASE("lens camera: a lens file that cannot be read fails the scene, naming camera.lens and the file",
          "[gpu][camera][lens]") {
    auto renderer = test::makeRenderer();
    std::string error;
    CHECK_FALSE(renderer->setScene(lensScene("/nonexistent/none.lens", 0.0f, 0), &error));
    CHECK(error == "camera.lens: /nonexistent/none.lens: cannot open the lens file");
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "caustic-bad-lens";
    std::filesystem::create_directories(dir);
    const std::string bad = (dir / "bad.lens").string();
    std::ofstream(bad) << "10 1 1.5 5\n-10 0 1\n";
    CHECK_FALSE(renderer->setScene(lensScene(bad, 0.0f, 0), &error));
    CHECK(error.find("camera.lens: " + bad + ":2: expected") == 0);
    // A lens with no stop reads, but is no camera.
    std::ofstream(bad) << "50 2 1.5 10\n-50 0 1 10\n";
    CHECK_FALSE(renderer->setScene(lensScene(bad, 0.0f, 0), &error));
    CHECK(error.find("no aperture stop") != std::string::npos);
    // The last good scene still renders.
    REQUIRE(renderer->setScene(lensScene(lensPath("dgauss-50mm.lens"), 0.0f, 0), &error));
    CHECK_FALSE(renderer->update(lensScene(bad, 0.0f, 0), kDirtyCamera, &error));
    CHECK(renderer->lensCamera() != nullptr);
    std::filesystem::remove_all(dir);
}

TEST_CASE("lens camera: picking and Shift+click focus work through the real lens", "[gpu][camera][lens][editor]") {
    auto renderer = test::makeRenderer();
    Scene s = lensScene(lensPath("dgauss-50mm.lens"), 4.0f, 0);
    s.camera.position = glm::vec3(0.3f, 0.8f, 2.5f);   // the ball off the image's centre
    s.camera.focalDistance = 30.0f;                    // focused far behind it
    std::string error;
    REQUIRE(renderer->setScene(s, &error));
    // The pixel at the ball's image: where the pinhole ray of `fov` would miss it (the lens's
    // field of view is not fov's), the lens's ray hits it.
    const int w = s.render.width, h = s.render.height;
    std::optional<glm::vec3> picked;
    glm::vec2 pixel(0.0f);
    for (int y = 0; y < h && !picked; y += 2)
        for (int x = 0; x < w && !picked; x += 2) {
            const glm::vec2 p(float(x) + 0.5f, float(y) + 0.5f);
            const editor::Ray lensRay = editor::cameraRay(s.camera, w, h, p, renderer->lensCamera());
            const editor::Ray pinhole = editor::cameraRay(s.camera, w, h, p);
            const auto a = editor::pick(s, lensRay), b = editor::pick(s, pinhole);
            // A point of the ball (object 1) the lens sees and the pinhole of fov does not.
            if (a && a->ref.index == 1 && (!b || b->ref.index != 1)) {
                picked = lensRay.origin + a->distance * lensRay.direction;
                pixel = p;
            }
        }
    REQUIRE(picked.has_value());
    const LensCamera focusedFar = *renderer->lensCamera();
    s.camera.focusPoint = *picked;
    REQUIRE(renderer->update(s, kDirtyCamera, &error));
    const LensCamera& cam = *renderer->lensCamera();
    // Every ray of that pixel's film point now meets the plane of focus (through the picked point)
    // in one spot: within the design's residual spot (a few um on the film), magnified to the
    // scene. The spot is the picked point up to focus breathing: focusing moves the lens, so the
    // film point sees a point a little off the one picked through the lens focused at 30 m.
    const glm::dvec2 ndc(2.0 * pixel.x / w - 1.0, 1.0 - 2.0 * pixel.y / h);
    const CameraFrame f = cameraFrame(s.camera, w, h);
    const double depth = glm::dot(glm::dvec3(*picked) - f.position, f.forward);
    // Where the rays of the pixel's film point meet the plane through the picked point, and the
    // rms distance of those spots from their centre.
    auto spotsOf = [&](const LensCamera& lens, glm::dvec3* centre) {
        const glm::dvec2 film(-ndc.x * lens.filmHalfWidth, -ndc.y * lens.filmHalfHeight);
        std::vector<glm::dvec3> spots;
        for (int j = 0; j < 12; ++j)
            for (int i = 0; i < 12; ++i) {
                double weight = 0.0;
                const auto r = lensCameraRay(lens, film, glm::dvec2((i + 0.5) / 12.0, (j + 0.5) / 12.0), -1, &weight);
                if (!r) continue;
                const glm::dvec3 o = f.position + 1e-3 * (r->o.x * f.right + r->o.y * f.up + (lens.filmZ - r->o.z) * f.forward);
                const glm::dvec3 d = glm::normalize(r->d.x * f.right + r->d.y * f.up - r->d.z * f.forward);
                spots.push_back(o + d * ((depth - glm::dot(o - f.position, f.forward)) / glm::dot(d, f.forward)));
            }
        *centre = glm::dvec3(0.0);
        for (const glm::dvec3& p : spots) *centre += p;
        *centre /= double(spots.size());
        double sq = 0.0;
        for (const glm::dvec3& p : spots) sq += glm::dot(p - *centre, p - *centre);
        CHECK(spots.size() > 50);
        return std::sqrt(sq / double(spots.size()));
    };
    glm::dvec3 centre, before;
    const double blurred = spotsOf(focusedFar, &before);
    const double spread = spotsOf(cam, &centre);
    const double offset = glm::length(centre - glm::dvec3(*picked));
    INFO("the picked pixel's rays meet the plane of focus " << spread << " rms from their centre (" << blurred
         << " before focusing there), " << offset << " from the picked point at depth " << depth);
    CHECK(spread < 0.1 * blurred);   // sharp now (off axis the design's coma and astigmatism remain)
    CHECK(offset < 0.02 * depth);    // breathing: the magnification changes by about 1 %
    // The focus distance is the picked point's depth from the film.
    CHECK(cam.focusDistanceMm == Approx(1000.0 * glm::dot(glm::dvec3(*picked) - f.position, f.forward)).epsilon(1e-6));
}

TEST_CASE("lens camera: the bokeh preview's points image to round discs at the centre and cat's eyes at the corners",
          "[gpu][camera][lens][editor]") {
    auto renderer = test::makeRenderer();
    Scene edited = lensScene(lensPath("dgauss-50mm.lens"), 0.0f, 0);   // wide open: the barrel cuts
    edited.render.width = 360;
    edited.render.height = 240;
    edited.camera.focalDistance = 0.5f;
    std::string error;
    REQUIRE(renderer->setScene(edited, &error));
    const Scene preview = editor::makeBokehPreviewScene(edited, renderer->lensCamera(), 192, 128);
    CHECK(preview.objects.size() == std::size_t(editor::kBokehPreviewColumns * editor::kBokehPreviewRows));
    CHECK(preview.camera == edited.camera);
    const Film wide = test::renderFilm(*renderer, preview, 128);
    // Each point's blob: the brightness-weighted spread of its cell of the grid along the
    // direction from the image's centre (radial) and across it (tangential).
    const int cols = editor::kBokehPreviewColumns, rows = editor::kBokehPreviewRows;
    auto spread = [&](const Film& film, int ci, int cj, double* radial, double* tangential, glm::dvec2* centroid) {
        const int x0 = ci * film.width / cols, x1 = (ci + 1) * film.width / cols;
        const int y0 = cj * film.height / rows, y1 = (cj + 1) * film.height / rows;
        double sum = 0.0;
        glm::dvec2 mean(0.0);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const double v = film.mean[film.index(x, y)].g;
                sum += v;
                mean += v * glm::dvec2(x + 0.5, y + 0.5);
            }
        REQUIRE(sum > 0.0);
        mean /= sum;
        if (centroid) *centroid = mean;
        glm::dvec2 axis = mean - glm::dvec2(film.width, film.height) * 0.5;
        axis = glm::length(axis) > 1.0 ? glm::normalize(axis) : glm::dvec2(1.0, 0.0);
        const glm::dvec2 across(-axis.y, axis.x);
        double r2 = 0.0, t2 = 0.0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const double v = film.mean[film.index(x, y)].g;
                const glm::dvec2 d = glm::dvec2(x + 0.5, y + 0.5) - mean;
                r2 += v * glm::dot(d, axis) * glm::dot(d, axis);
                t2 += v * glm::dot(d, across) * glm::dot(d, across);
            }
        *radial = std::sqrt(r2 / sum);
        *tangential = std::sqrt(t2 / sum);
    };
    double cr = 0.0, ct = 0.0, er = 0.0, et = 0.0;
    glm::dvec2 cornerPixel(0.0);
    spread(wide, cols / 2, rows / 2, &cr, &ct, nullptr);
    spread(wide, 0, 0, &er, &et, &cornerPixel);
    // The same shapes from the exit-pupil bound alone (renderer/lens.h): the spread of the pupil
    // points whose rays pass, for the film points under the blobs, and their area (the passing
    // share of the bound times its area).
    const LensCamera& cam = *renderer->lensCamera();
    auto pupil = [&](double r) {
        const test::PupilShape p = test::passingPupil(cam, r, 160);
        return glm::dvec3(p.radial, p.tangential, p.area);
    };
    const glm::dvec2 cornerNdc(2.0 * cornerPixel.x / wide.width - 1.0, 1.0 - 2.0 * cornerPixel.y / wide.height);
    const double cornerFilm = glm::length(cornerNdc * glm::dvec2(cam.filmHalfWidth, cam.filmHalfHeight));
    const glm::dvec3 pc = pupil(0.0), pe = pupil(cornerFilm);
    INFO("centre blob " << cr << " x " << ct << " px (radial x tangential), corner blob " << er << " x " << et
                        << "; the passing pupil: centre " << pc.x << " x " << pc.y << " mm, area " << pc.z
                        << " mm^2, corner " << pe.x << " x " << pe.y << ", area " << pe.z);
    CHECK(cr > 3.0);                              // defocused: a disc, not a point
    CHECK(cr == Approx(ct).epsilon(0.1));         // round at the centre
    CHECK(er < 0.8 * et);                         // a cat's eye at the corner, narrow radially
    // The rendered cat's eye has the passing pupil's proportions, and its size relative to the
    // centre's disc is the passing pupil's.
    CHECK(er / et == Approx(pe.x / pe.y).epsilon(0.1));
    CHECK(er * et / (cr * ct) == Approx(pe.x * pe.y / (pc.x * pc.y)).epsilon(0.15));
    std::printf("bokeh preview, double Gauss wide open: corner / centre blob area (second moments) %.3f rendered, "
                "%.3f from the pupil bound; passing pupil area %.1f / %.1f mm^2\n", er * et / (cr * ct),
                pe.x * pe.y / (pc.x * pc.y), pe.z, pc.z);
    // Stopped down to f/8, the barrel no longer cuts the corner's bundle: round again.
    Scene stopped = edited;
    stopped.camera.lensFStop = 8.0f;
    REQUIRE(renderer->setScene(stopped, &error));
    const Film small = test::renderFilm(*renderer, editor::makeBokehPreviewScene(stopped, renderer->lensCamera(), 192, 128), 128);
    double sr = 0.0, st = 0.0;
    spread(small, 0, 0, &sr, &st, nullptr);
    INFO("stopped down to f/8: corner blob " << sr << " x " << st);
    CHECK(sr > 0.85 * st);
}

TEST_CASE("lens camera: rays the lens blocks count as dark samples but not in the albedo and normal AOVs",
          "[gpu][camera][lens][aov]") {
    // A grey wall filling the view of the double Gauss, wide open: the corners are vignetted (a
    // third or more of their rays blocked), darker in the image, and their albedo is still the wall's.
    Scene s;
    s.render.width = 48;
    s.render.height = 32;
    s.render.maxDepth = 1;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(0.0f)});
    Object wall;
    wall.shape = Shape::Quad;
    wall.material = "grey";
    wall.transform.scale = glm::vec3(20.0f);
    s.objects.push_back(wall);
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(1.0f);
    s.camera.position = glm::vec3(0.0f, 0.0f, 3.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.lens = lensPath("dgauss-50mm.lens");
    for (bool regenerate : {true, false}) {
        IntegratorConfig config = test::testConfig();
        config.regenerate = regenerate;
        auto renderer = test::makeRenderer(config);
        const Film film = test::renderFilm(*renderer, s, 16);
        double worst = 0.0;
        for (std::size_t i = 0; i < film.albedo.size(); ++i) worst = std::max(worst, double(std::abs(film.albedo[i].g - 0.5f)));
        const glm::vec3 centre = film.mean[film.index(24, 16)], corner = film.mean[film.index(0, 0)];
        INFO((regenerate ? "regeneration" : "whole paths") << ": albedo AOV off the wall's by up to " << worst
                                                           << "; radiance at the centre " << centre.g << ", corner " << corner.g);
        CHECK(worst < 1e-3);
        CHECK(corner.g < 0.8f * centre.g);   // the corner is vignetted in the image itself
    }
}
