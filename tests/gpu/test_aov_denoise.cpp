// The AOVs (albedo and normal at each path's first non-specular vertex) and the denoiser.
//   1. Through a smooth glass sphere the AOVs show the wall behind it (its albedo, its normal);
//      an opaque sphere in the same place shows itself; where camera paths escape they are 0.
//   2. Open Image Denoise on a noisy Cornell box (64x64, 4 spp) lowers the error against a
//      256-spp reference by a large factor and keeps the image mean. The reference's own noise is
//      removed from the squared error: E[(x - ref)^2] = E[(x - truth)^2] + Var(ref), and Var(ref)
//      per pixel is known from the reference's sum of squares. The numbers are printed.
#include "renderer/denoise.h"
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

using namespace caustic;

namespace {

// A green diffuse wall at z = -2 (normal +z, towards the camera), a sphere of radius 0.6 at the
// origin, a white sky; the camera on +z sees the wall around the sphere and the sky at the corners.
Scene wallAndSphere(MaterialType sphereType) {
    Scene s;
    s.render.width = s.render.height = 32;
    s.render.maxDepth = 8;
    s.render.seed = 3;
    s.camera.position = glm::vec3(0.0f, 0.0f, 4.0f);
    s.camera.fovDegrees = 40.0f;
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(1.0f);
    Material wall{"wall", MaterialType::Diffuse, glm::vec3(0.2f, 0.6f, 0.3f), glm::vec3(0.0f)};
    Material ball{"ball", sphereType, glm::vec3(0.7f, 0.1f, 0.1f), glm::vec3(0.0f)};
    s.materials = {wall, ball};
    Object quad;
    quad.shape = Shape::Quad;
    quad.material = "wall";
    quad.transform.translate = glm::vec3(0.0f, 0.0f, -2.0f);
    quad.transform.scale = glm::vec3(1.8f);  // the view is 4.4 wide at z = -2: its corners miss the wall
    Object sphere;
    sphere.shape = Shape::Sphere;
    sphere.material = "ball";
    sphere.transform.scale = glm::vec3(0.6f);
    s.objects = {quad, sphere};
    return s;
}

glm::vec3 centreMean(const std::vector<glm::vec3>& v, int size) {
    glm::vec3 sum(0.0f);
    for (int y = size / 2 - 2; y < size / 2 + 2; ++y)
        for (int x = size / 2 - 2; x < size / 2 + 2; ++x) sum += v[static_cast<size_t>(y) * size + x];
    return sum / 16.0f;
}

}  // namespace

TEST_CASE("AOVs through a glass sphere show the surface behind it", "[gpu][aov]") {
    auto renderer = test::makeRenderer();
    const int n = 32;

    // Opaque sphere: its own albedo and the normal facing the camera (+z) at the centre.
    Film opaque = test::renderFilm(*renderer, wallAndSphere(MaterialType::Diffuse), 8);
    glm::vec3 a = centreMean(opaque.albedo, n), nn = centreMean(opaque.normal, n);
    INFO("opaque sphere: albedo " << a.x << " " << a.y << " " << a.z << ", normal " << nn.x << " " << nn.y << " " << nn.z);
    CHECK(std::abs(a.x - 0.7f) < 1e-4f);
    CHECK(std::abs(a.y - 0.1f) < 1e-4f);
    CHECK(nn.z > 0.95f);

    // Glass sphere (ior 1.5): the path passes through two delta vertices and lands on the wall.
    // Fresnel reflection at the two interfaces (~4% each at normal incidence) sends a few paths
    // back to the sky, where they record 0: the albedo is the wall's times about 0.92.
    Film glass = test::renderFilm(*renderer, wallAndSphere(MaterialType::Dielectric), 32);
    a = centreMean(glass.albedo, n);
    nn = centreMean(glass.normal, n);
    INFO("glass sphere: albedo " << a.x << " " << a.y << " " << a.z << ", normal " << nn.x << " " << nn.y << " " << nn.z);
    CHECK(a.y > 0.6f * 0.85f);
    CHECK(a.y <= 0.6f + 1e-4f);
    CHECK(std::abs(a.x / a.y - 0.2f / 0.6f) < 0.02f);  // the wall's colour, not the sphere's
    CHECK(std::abs(a.z / a.y - 0.3f / 0.6f) < 0.02f);
    CHECK(nn.z > 0.8f);  // the wall's normal (+z), weighted by the same ~0.92
    CHECK(std::abs(nn.x) < 0.05f);
    CHECK(std::abs(nn.y) < 0.05f);

    // A corner pixel sees only the sky: both AOVs are 0. A pixel on the wall away from the
    // sphere: the wall's albedo and normal exactly.
    CHECK(glass.albedo[0] == glm::vec3(0.0f));
    CHECK(glass.normal[0] == glm::vec3(0.0f));
    const size_t wallPixel = static_cast<size_t>(n / 2) * n + 4;
    CHECK(glm::length(glass.albedo[wallPixel] - glm::vec3(0.2f, 0.6f, 0.3f)) < 1e-4f);
    CHECK(glm::length(glass.normal[wallPixel] - glm::vec3(0.0f, 0.0f, 1.0f)) < 1e-4f);
}

#ifdef CAUSTIC_HAVE_OIDN

TEST_CASE("Open Image Denoise reduces the error of a noisy Cornell box and keeps its mean", "[gpu][denoise]") {
    SceneLoadResult loaded = loadScene(CAUSTIC_SOURCE_DIR "/scenes/cornell-box.json");
    INFO(loaded.error);
    REQUIRE(loaded);
    Scene s = *loaded.scene;
    s.render.width = s.render.height = 64;
    auto renderer = test::makeRenderer();
    s.render.seed = 100;
    const Film ref = test::renderFilm(*renderer, s, 256);
    s.render.seed = 1;
    const Film noisy = test::renderFilm(*renderer, s, 4);

    // Squared error against the truth, estimated (see the top of the file). relMSE divides each
    // pixel's squared error by ref^2 + 0.01 (the relative error of denoising papers, e.g. Rousselle
    // et al. 2011), over the whole image. RMSE is over the pixels whose reference is below 1 in
    // every channel: the directly seen light (radiance ~17) and its partly covered edge pixels would
    // otherwise make up most of the sum, and they are not where the noise is.
    struct Errors { double rmse, relMse; glm::dvec3 mean, dimMean; };
    auto errors = [&](const std::vector<glm::vec3>& img) {
        Errors e{0.0, 0.0, glm::dvec3(0.0), glm::dvec3(0.0)};
        double dim = 0.0;
        for (size_t i = 0; i < img.size(); ++i) {
            const bool lit = glm::max(ref.mean[i].x, glm::max(ref.mean[i].y, ref.mean[i].z)) >= 1.0f;
            if (!lit) dim += 3.0;
            for (int c = 0; c < 3; ++c) {
                const double d = double(img[i][c]) - ref.mean[i][c];
                const double se = d * d - ref.varianceOfMean[i][c];
                if (!lit) e.rmse += se;
                if (!lit) e.dimMean[c] += img[i][c];
                e.relMse += se / (double(ref.mean[i][c]) * ref.mean[i][c] + 0.01);
                e.mean[c] += img[i][c];
            }
        }
        const double count = double(img.size());
        e.rmse = std::sqrt(std::max(e.rmse / dim, 0.0));
        e.relMse /= 3.0 * count;
        e.mean /= count;
        e.dimMean /= dim / 3.0;
        return e;
    };
    const Errors before = errors(noisy.mean);
    std::printf("denoise: noisy 4 spp: RMSE %.4f, relMSE %.4f, mean %.4f %.4f %.4f\n", before.rmse, before.relMse,
                before.mean.x, before.mean.y, before.mean.z);

    for (const char* mode : {"prefiltered guides", "raw guides", "no guides"}) {
        DenoiseOptions opt;
        opt.useGuides = std::string(mode) != "no guides";
        opt.prefilterGuides = std::string(mode) == "prefiltered guides";
        DenoiseResult result;
        std::string error;
        const bool ok = denoise(noisy, opt, &result, &error);
        INFO(error);
        REQUIRE(ok);
        REQUIRE(result.image.size() == noisy.mean.size());
        const Errors after = errors(result.image);
        std::printf("denoise (%s, %s): RMSE %.4f (%.1fx lower), relMSE %.4f (%.1fx lower), mean %.4f %.4f %.4f\n",
                    mode, result.device.c_str(), after.rmse, before.rmse / after.rmse, after.relMse,
                    before.relMse / after.relMse, after.mean.x, after.mean.y, after.mean.z);
        INFO(mode << ": RMSE " << before.rmse << " -> " << after.rmse << ", relMSE " << before.relMse << " -> "
                  << after.relMse);
        // Measured on llvmpipe + the CPU device: RMSE 3.6x, relMSE 10.6x lower with prefiltered
        // guides; 2.8x / 6.6x with raw guides; 3.4x / 8.9x with colour alone.
        CHECK(after.rmse < (opt.prefilterGuides ? 1.0 / 3.0 : 0.5) * before.rmse);
        CHECK(after.relMse < (opt.prefilterGuides ? 1.0 / 8.0 : 0.25) * before.relMse);
        // The mean is kept (the default, prefiltered guides; the others are reported above):
        // within 2% where the noise is (the pixels the RMSE counts), within 4% over the whole
        // image, where the directly seen light (radiance ~17, a white reflecting quad since
        // issue 13, so its albedo guide is white, not black) dominates the sum and OIDN reshapes
        // its edge pixels (measured: -2.3% in G and B over the whole image).
        if (opt.prefilterGuides)
            for (int c = 0; c < 3; ++c) {
                INFO("channel " << c << ": noisy mean " << before.mean[c] << ", denoised mean " << after.mean[c]
                                << "; below 1: " << before.dimMean[c] << " -> " << after.dimMean[c]);
                CHECK(std::abs(after.dimMean[c] - before.dimMean[c]) < 0.02 * before.dimMean[c]);
                CHECK(std::abs(after.mean[c] - before.mean[c]) < 0.04 * before.mean[c]);
            }
    }
}

#else

TEST_CASE("without Open Image Denoise, denoise() fails with a message that says so", "[denoise]") {
    REQUIRE_FALSE(denoiserAvailable());
    DenoiseResult result;
    std::string error;
    CHECK_FALSE(denoise(Film{}, {}, &result, &error));
    CHECK(error.find("Open Image Denoise") != std::string::npos);
}

#endif
