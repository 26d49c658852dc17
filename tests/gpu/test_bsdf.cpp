// The BSDF models through the real GLSL (tests/gpu/kernels/bsdf_eval.comp includes the same
// bsdf/bsdf.glsl as the integrator), tested the way pbrt-v4 (bsdfs_test.cpp) and Mitsuba 3
// (chi2.py) test theirs:
//   - chi-square goodness of fit of every sampled lobe against its pdf, binned in (theta, phi)
//     over the whole sphere, for normal, oblique, grazing, below-the-horizon and total-internal-
//     reflection directions and several roughness values, Sidak-corrected over the suite;
//   - the pdf integrates to the fraction of samples that are valid (and so to at most 1, and to 1
//     where nothing is lost);
//   - every sample's weight equals eval |cos| / pdf, and its pdf equals bsdfPdf;
//   - reciprocity of the reflection lobes;
//   - white furnaces: the mean sample weight (the directional albedo) per model and direction.
#include "renderer/gpu_scene.h"
#include "renderer/bsdf_tables.h"
#include "renderer/shader_loader.h"
#include "tests/gpu/gl_fixture.h"
#include "tests/support/chi2.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace caustic;

namespace {

constexpr double kPi = 3.14159265358979323846;

GLuint bsdfKernel() { return test::kernel("bsdf_eval.comp"); }

gpu::GpuMaterial material(std::uint32_t type, glm::vec3 albedo, float roughness = 0.0f, float ior = 1.5f,
                          std::uint32_t flags = 0) {
    gpu::GpuMaterial m{};
    m.albedo = glm::vec4(albedo, 0);
    m.params = glm::vec4(roughness, ior, 0, 0);
    m.info = glm::uvec4(type, flags, 0, 0);
    // Gold (the preset), so that conductor tests see a coloured, angle-dependent Fresnel.
    m.eta = glm::vec4(0.183f, 0.421f, 1.373f, 0);
    m.k = glm::vec4(3.424f, 2.346f, 1.770f, 0);
    return m;
}

// The layered surface material (shaders/bsdf/surface.glsl), with GGX alphas (not perceptual).
struct SurfaceParams {
    glm::vec3 base{1.0f};
    float metalness = 0.0f;
    float specWeight = 1.0f, specAlpha = 0.2f, specIor = 1.5f;
    glm::vec3 specColor{1.0f};
    float coatWeight = 0.0f, coatAlpha = 0.1f, coatIor = 1.6f;
    glm::vec3 coatColor{1.0f};
    glm::vec3 sheen{0.0f};
    float sheenRoughness = 0.3f;
};

gpu::GpuMaterial surface(const SurfaceParams& p) {
    gpu::GpuMaterial m{};
    m.albedo = glm::vec4(p.base, p.metalness);
    m.params = glm::vec4(p.specAlpha, p.specIor, p.specWeight, p.coatWeight);
    m.eta = glm::vec4(p.specColor, p.coatAlpha);
    m.k = glm::vec4(p.coatColor, p.coatIor);
    m.sheen = glm::vec4(p.sheen, p.sheenRoughness);
    m.info = glm::uvec4(MAT_SURFACE, 0, 0, 0);
    return m;
}

// One of each lobe combination the issue names: base only, base + specular, + coat, + sheen,
// metal, and everything at once.
struct SurfaceCase { const char* name; SurfaceParams p; };
std::vector<SurfaceCase> surfaceCombinations() {
    SurfaceParams diffuse;
    diffuse.base = glm::vec3(0.7f, 0.5f, 0.3f);
    diffuse.specWeight = 0.0f;
    SurfaceParams plastic = diffuse;
    plastic.specWeight = 1.0f;
    plastic.specAlpha = 0.15f;
    SurfaceParams coated = plastic;
    coated.specAlpha = 0.5f;
    coated.coatWeight = 1.0f;
    coated.coatAlpha = 0.1f;
    coated.coatColor = glm::vec3(0.9f, 0.85f, 0.7f);
    SurfaceParams velvet = plastic;
    velvet.sheen = glm::vec3(0.9f, 0.3f, 0.5f);
    velvet.sheenRoughness = 0.4f;
    SurfaceParams metal;
    metal.base = glm::vec3(0.95f, 0.7f, 0.35f);
    metal.metalness = 1.0f;
    metal.specAlpha = 0.3f;
    metal.specColor = glm::vec3(0.9f, 0.8f, 0.7f);
    SurfaceParams all = coated;
    all.metalness = 0.4f;
    all.sheen = glm::vec3(0.4f);
    all.sheenRoughness = 0.8f;
    return {{"surface base only", diffuse}, {"surface base + specular", plastic}, {"surface + coat", coated},
            {"surface + sheen", velvet},    {"surface metal", metal},            {"surface everything", all}};
}

glm::vec3 directionWithCos(float cosTheta, float phi = 0.3f) {
    float s = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    return {s * std::cos(phi), s * std::sin(phi), cosTheta};
}

// One renderer (for the scene buffers, the GGX table among them) and a material buffer.
class Harness {
public:
    Harness() : m_renderer(test::makeRenderer()) {
        Scene s;
        s.render.width = s.render.height = 1;
        std::string error;
        REQUIRE(m_renderer->setScene(s, &error));
        glCreateBuffers(1, &m_material);
        glCreateBuffers(1, &m_out);
    }
    ~Harness() {
        glDeleteBuffers(1, &m_material);
        glDeleteBuffers(1, &m_out);
    }
    Harness(const Harness&) = delete;
    Harness& operator=(const Harness&) = delete;

    void setMaterial(const gpu::GpuMaterial& m) { glNamedBufferData(m_material, sizeof m, &m, GL_STATIC_DRAW); }

    std::vector<glm::vec4> run(GLuint mode, GLuint count, GLuint outputs, glm::vec3 wo, GLuint rows = 0,
                               GLuint cols = 1, GLuint sub = 1, GLuint seed = 1234) {
        GLuint p = bsdfKernel();
        const size_t n = size_t(count) * outputs;
        glNamedBufferData(m_out, GLsizeiptr(n * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
        m_renderer->bindScene(0, 1);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_MATERIALS, m_material);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, m_out);
        glUseProgram(p);
        glProgramUniform1ui(p, glGetUniformLocation(p, "u_mode"), mode);
        glProgramUniform1ui(p, glGetUniformLocation(p, "u_count"), count);
        glProgramUniform1ui(p, glGetUniformLocation(p, "u_material"), 0);
        glProgramUniform3f(p, glGetUniformLocation(p, "u_wo"), wo.x, wo.y, wo.z);
        glProgramUniform1ui(p, glGetUniformLocation(p, "u_rows"), rows);
        glProgramUniform1ui(p, glGetUniformLocation(p, "u_cols"), cols);
        glProgramUniform1ui(p, glGetUniformLocation(p, "u_sub"), sub);
        glProgramUniform1ui(p, glGetUniformLocation(p, "u_seed"), seed);
        glDispatchCompute((count + 63) / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<glm::vec4> r(n);
        glGetNamedBufferSubData(m_out, 0, GLsizeiptr(n * sizeof(glm::vec4)), r.data());
        REQUIRE(glDebugErrorCount() == 0);
        return r;
    }

    struct Samples {
        std::vector<glm::vec3> wi;
        std::vector<float> pdf;
        std::vector<glm::vec3> weight;
        std::vector<std::uint32_t> flags;
        std::vector<glm::vec3> eval;
        std::vector<float> pdfEval;
    };
    Samples sample(glm::vec3 wo, GLuint count, GLuint seed = 1234) {
        std::vector<glm::vec4> r = run(0, count, 3, wo, 0, 1, 1, seed);
        Samples s;
        for (GLuint i = 0; i < count; ++i) {
            s.wi.emplace_back(r[3 * i]);
            s.pdf.push_back(r[3 * i].w);
            s.weight.emplace_back(r[3 * i + 1]);
            s.flags.push_back(std::uint32_t(r[3 * i + 1].w));
            s.eval.emplace_back(r[3 * i + 2]);
            s.pdfEval.push_back(r[3 * i + 2].w);
        }
        return s;
    }

private:
    std::unique_ptr<Renderer> m_renderer;
    GLuint m_material = 0, m_out = 0;
};

Harness& harness() {
    static Harness h;
    return h;
}

// The directional albedo: the mean weight, transmitted samples times etap^2 (undoing the radiance
// scaling, which is not a loss of energy; see shaders/bsdf/specular.glsl).
double furnace(const Harness::Samples& s, glm::vec3 wo, float eta) {
    double sum = 0.0;
    for (size_t i = 0; i < s.wi.size(); ++i) {
        if (!(s.pdf[i] > 0.0f)) continue;
        double w = s.weight[i].g;
        if (s.flags[i] & 2u) {
            double etap = wo.z > 0.0f ? eta : 1.0 / eta;
            w *= etap * etap;
        }
        sum += w;
    }
    return sum / double(s.wi.size());
}

// The directional albedo of the qualitative Oren-Nayar BRDF (Oren & Nayar 1994, eq. 30, with the
// global compensation factor when asked) at cos(theta_o) = mu, albedo 1, by the midpoint rule over
// the hemisphere of wi (512 x 512 points in theta, phi), in double precision and written from the
// formula, not from the shader.
double orenNayarAlbedo(double sigma, double mu, bool compensated) {
    const double pi = 3.14159265358979323846, s2 = sigma * sigma;
    const double A = 1.0 - s2 / (2.0 * (s2 + 0.33)), B = 0.45 * s2 / (s2 + 0.09);
    const double scale = compensated ? 1.0 / (1.0 - 0.33 * s2 / (s2 + 0.09)) : 1.0;
    const double thetaO = std::acos(mu);
    constexpr int N = 512;
    double sum = 0.0;
    for (int i = 0; i < N; ++i) {
        const double thetaI = 0.5 * pi * (i + 0.5) / N;
        const double alpha = std::max(thetaI, thetaO), beta = std::min(thetaI, thetaO);
        double ring = 0.0;
        for (int j = 0; j < N; ++j) {
            const double dphi = 2.0 * pi * (j + 0.5) / N;  // phi_i - phi_o
            ring += A + B * std::max(0.0, std::cos(dphi)) * std::sin(alpha) * std::tan(beta);
        }
        sum += ring / N * 2.0 * pi * std::cos(thetaI) * std::sin(thetaI) * (0.5 * pi / N);
    }
    return scale * sum / pi;
}

constexpr GLuint kRows = 32, kCols = 32, kSub = 32;
constexpr GLuint kSamples = 1u << 19;

struct Chi2Case {
    const char* name;
    gpu::GpuMaterial mat;
    glm::vec3 wo;
};

std::vector<Chi2Case> chi2Cases() {
    std::vector<Chi2Case> cases;
    const glm::vec3 normal(0, 0, 1), oblique = directionWithCos(0.5f), grazing = directionWithCos(0.05f);
    cases.push_back({"lambert normal", material(MAT_DIFFUSE, glm::vec3(0.7f)), normal});
    cases.push_back({"lambert oblique", material(MAT_DIFFUSE, glm::vec3(0.7f)), oblique});
    cases.push_back({"oren-nayar oblique", material(MAT_OREN_NAYAR, glm::vec3(0.7f), 0.6f), oblique});
    cases.push_back({"eon oblique", material(MAT_EON, glm::vec3(0.7f), 0.7f), oblique});
    static const char* kConductorNames[3][3] = {
        {"conductor a=0.1 normal", "conductor a=0.1 oblique", "conductor a=0.1 grazing"},
        {"conductor a=0.35 normal", "conductor a=0.35 oblique", "conductor a=0.35 grazing"},
        {"conductor a=0.8 normal", "conductor a=0.8 oblique", "conductor a=0.8 grazing"}};
    static const char* kDielectricNames[3][5] = {
        {"glass a=0.1 normal", "glass a=0.1 oblique", "glass a=0.1 grazing", "glass a=0.1 inside",
         "glass a=0.1 inside beyond the critical angle"},
        {"glass a=0.35 normal", "glass a=0.35 oblique", "glass a=0.35 grazing", "glass a=0.35 inside",
         "glass a=0.35 inside beyond the critical angle"},
        {"glass a=0.8 normal", "glass a=0.8 oblique", "glass a=0.8 grazing", "glass a=0.8 inside",
         "glass a=0.8 inside beyond the critical angle"}};
    const float alphas[3] = {0.1f, 0.35f, 0.8f};
    for (int a = 0; a < 3; ++a) {
        const glm::vec3 wos[3] = {normal, oblique, grazing};
        for (int w = 0; w < 3; ++w)
            cases.push_back({kConductorNames[a][w], material(MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), alphas[a]), wos[w]});
        // Inside: cos -0.9 refracts out; cos -0.5 (60 degrees) is beyond the critical angle of
        // 41.8 degrees for eta 1.5, where only rough microfacets let light out.
        const glm::vec3 gwos[5] = {normal, oblique, grazing, directionWithCos(-0.9f), directionWithCos(-0.5f)};
        for (int w = 0; w < 5; ++w)
            cases.push_back({kDielectricNames[a][w], material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), alphas[a], 1.5f), gwos[w]});
    }
    // Rough transmission alone (no reflection lobe but under total internal reflection).
    const gpu::GpuMaterial roughTransmission =
        material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.35f, 1.5f, MAT_FLAG_NO_REFLECTION);
    cases.push_back({"rough transmission a=0.35 normal", roughTransmission, normal});
    cases.push_back({"rough transmission a=0.35 oblique", roughTransmission, oblique});
    cases.push_back({"rough transmission a=0.35 inside", roughTransmission, directionWithCos(-0.9f)});
    cases.push_back({"rough transmission a=0.35 inside beyond the critical angle", roughTransmission, directionWithCos(-0.5f)});
    // Thin-walled sheets (bsdf/thin.glsl): the rough thin dielectric (its transmission the mirrored
    // reflection lobe) and the diffuse transmitter, from either face.
    gpu::GpuMaterial thin = material(MAT_THIN_DIELECTRIC, glm::vec3(0.9f, 0.6f, 0.3f), 0.35f, 1.5f);
    cases.push_back({"thin dielectric a=0.35 oblique", thin, oblique});
    cases.push_back({"thin dielectric a=0.35 from behind", thin, directionWithCos(-0.7f)});
    thin.params.x = 0.8f;
    cases.push_back({"thin dielectric a=0.8 grazing", thin, grazing});
    gpu::GpuMaterial translucent = material(MAT_DIFFUSE_TRANSMISSION, glm::vec3(0.6f, 0.5f, 0.4f));
    translucent.eta = glm::vec4(0.2f, 0.3f, 0.5f, 0.0f);
    translucent.params = glm::vec4(0.2f, 1.45f, 0.0f, 0.0f);
    translucent.k = glm::vec4(0.0f);  // no specular layer
    cases.push_back({"diffuse transmission oblique", translucent, oblique});
    translucent.k.x = 1.0f;  // under a specular layer of alpha 0.2
    cases.push_back({"diffuse transmission + specular oblique", translucent, oblique});
    cases.push_back({"diffuse transmission + specular from behind", translucent, directionWithCos(-0.4f)});
    // The layered surface: every lobe combination at an oblique view, the full stack also at
    // normal and grazing incidence.
    static std::vector<std::string> surfaceNames;
    surfaceNames.clear();
    for (const SurfaceCase& c : surfaceCombinations()) surfaceNames.push_back(std::string(c.name) + " oblique");
    surfaceNames.push_back("surface everything normal");
    surfaceNames.push_back("surface everything grazing");
    const std::vector<SurfaceCase> combos = surfaceCombinations();
    for (size_t i = 0; i < combos.size(); ++i) cases.push_back({surfaceNames[i].c_str(), surface(combos[i].p), oblique});
    cases.push_back({surfaceNames[combos.size()].c_str(), surface(combos.back().p), normal});
    cases.push_back({surfaceNames[combos.size() + 1].c_str(), surface(combos.back().p), grazing});
    return cases;
}

}  // namespace

TEST_CASE("BSDF sampling matches the pdf (chi-square), and the pdf integrates to the valid fraction",
          "[gpu][bsdf][chi2]") {
    Harness& h = harness();
    const std::vector<Chi2Case> cases = chi2Cases();
    for (const Chi2Case& c : cases) {
        INFO(c.name);
        h.setMaterial(c.mat);
        Harness::Samples s = h.sample(c.wo, kSamples);
        std::vector<glm::vec4> cells = h.run(1, kRows * kCols, 1, c.wo, kRows, kCols, kSub);
        std::vector<double> observed(kRows * kCols, 0.0), expected(kRows * kCols, 0.0);
        double valid = 0.0, integral = 0.0;
        for (size_t i = 0; i < s.wi.size(); ++i) {
            if (!(s.pdf[i] > 0.0f)) continue;
            valid += 1.0;
            glm::dvec3 w = glm::normalize(glm::dvec3(s.wi[i]));
            int row = std::clamp(int(std::acos(std::clamp(w.z, -1.0, 1.0)) / kPi * kRows), 0, int(kRows) - 1);
            double phi = std::atan2(w.y, w.x);
            if (phi < 0.0) phi += 2.0 * kPi;
            int col = std::clamp(int(phi / (2.0 * kPi) * kCols), 0, int(kCols) - 1);
            observed[size_t(row) * kCols + size_t(col)] += 1.0;
        }
        for (size_t i = 0; i < cells.size(); ++i) {
            integral += cells[i].x;
            expected[i] = double(cells[i].x) * kSamples;
        }
        const double validFraction = valid / kSamples;
        CHECK(integral <= 1.002);
        CHECK(integral == Approx(validFraction).margin(0.004));
        test::Chi2Result r = test::chi2Test(observed, expected, kRows, kCols, 0.01, int(cases.size()));
        std::printf("chi2 %-48s valid %.4f  pdf integral %.4f  chi2 %.1f dof %d p %.3g\n", c.name, validFraction,
                    integral, r.statistic, r.dof, r.pValue);
        INFO(r.report);
        CHECK(r.passed);
    }
}

TEST_CASE("BSDF sample weights equal eval |cos| / pdf, and pdfs equal bsdfPdf", "[gpu][bsdf]") {
    Harness& h = harness();
    for (const Chi2Case& c : chi2Cases()) {
        INFO(c.name);
        h.setMaterial(c.mat);
        Harness::Samples s = h.sample(c.wo, 1u << 14, 99);
        int bad = 0, checked = 0;
        for (size_t i = 0; i < s.wi.size(); ++i) {
            if (!(s.pdf[i] > 0.0f)) continue;
            ++checked;
            glm::vec3 expect = s.eval[i] * std::abs(s.wi[i].z) / s.pdfEval[i];
            float scale = std::max(1e-3f, std::max(expect.x, std::max(expect.y, expect.z)));
            bool ok = glm::all(glm::lessThanEqual(glm::abs(expect - s.weight[i]), glm::vec3(2e-3f * scale))) &&
                      std::abs(s.pdf[i] - s.pdfEval[i]) <= 2e-3f * s.pdf[i];
            if (!ok && bad++ < 5) {
                INFO("sample " << i << ": weight " << s.weight[i].x << " vs eval*cos/pdf " << expect.x << ", pdf "
                               << s.pdf[i] << " vs " << s.pdfEval[i]);
                CHECK(ok);
            }
        }
        CHECK(checked > 1000);
        CHECK(bad <= 2);  // rounding at the very edges of the lobes
    }
}

TEST_CASE("BSDF reflection lobes are reciprocal", "[gpu][bsdf]") {
    Harness& h = harness();
    struct Case { const char* name; gpu::GpuMaterial mat; };
    const Case cases[] = {
        {"lambert", material(MAT_DIFFUSE, glm::vec3(0.7f))},
        {"oren-nayar", material(MAT_OREN_NAYAR, glm::vec3(0.7f), 0.8f)},
        {"oren-nayar compensated", material(MAT_OREN_NAYAR, glm::vec3(0.7f), 0.8f, 1.5f, MAT_FLAG_ENERGY_COMPENSATION)},
        {"eon", material(MAT_EON, glm::vec3(0.7f), 0.8f)},
        {"rough conductor", material(MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), 0.3f)},
        {"rough dielectric reflection", material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.3f, 1.5f)},
        // The layered surface's reciprocal part: specular over diffuse, and the metal (its coat and
        // sheen layers scale by their albedo at wo only: shaders/bsdf/surface.glsl).
        {"surface base + specular", surface(surfaceCombinations()[1].p)},
        {"surface metal", surface(surfaceCombinations()[4].p)},
        {"surface metal + specular mix", [] {
             SurfaceParams p = surfaceCombinations()[1].p;
             p.metalness = 0.5f;
             return surface(p);
         }()},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        h.setMaterial(c.mat);
        std::vector<glm::vec4> r = h.run(2, 4096, 2, glm::vec3(0, 0, 1));
        int bad = 0;
        for (size_t i = 0; i < 4096; ++i) {
            glm::vec3 a(r[2 * i]), b(r[2 * i + 1]);
            float scale = std::max(1e-4f, std::max(a.x, b.x));
            if (std::abs(a.x - b.x) > 1e-3f * scale) ++bad;
        }
        CHECK(bad == 0);
    }
}

TEST_CASE("BSDF white furnace: directional albedo per model", "[gpu][bsdf][furnace]") {
    Harness& h = harness();
    const GLuint n = 1u << 18;
    const float cosines[] = {1.0f, 0.5f, 0.1f};
    SECTION("lossless models reflect exactly 1") {
        struct Case { const char* name; gpu::GpuMaterial mat; double tolerance; };
        const Case cases[] = {
            {"lambert", material(MAT_DIFFUSE, glm::vec3(1.0f)), 0.003},
            {"eon r=0.3", material(MAT_EON, glm::vec3(1.0f), 0.3f), 0.006},
            {"eon r=1", material(MAT_EON, glm::vec3(1.0f), 1.0f), 0.006},
            {"mirror", material(MAT_MIRROR, glm::vec3(1.0f)), 1e-6},
            {"smooth conductor F=1", material(MAT_CONDUCTOR, glm::vec3(1.0f), 0.0f, 1.5f, MAT_FLAG_FRESNEL_ONE), 1e-6},
            {"perfect transmission ior 1.33", material(MAT_TRANSMISSION, glm::vec3(1.0f), 0.0f, 1.33f), 1e-5},
            {"smooth glass ior 1.5", material(MAT_DIELECTRIC, glm::vec3(1.0f), 0.0f, 1.5f), 1e-5},
        };
        for (const Case& c : cases) {
            h.setMaterial(c.mat);
            for (float cosTheta : cosines) {
                const glm::vec3 wo = directionWithCos(cosTheta);
                double e = furnace(h.sample(wo, n), wo, c.mat.params.y);
                std::printf("furnace %-32s cos %.2f: %.5f\n", c.name, double(cosTheta), e);
                INFO(c.name << " cos " << cosTheta);
                CHECK(e == Approx(1.0).margin(c.tolerance));
            }
        }
        // Glass from inside, below and beyond the critical angle (total internal reflection).
        h.setMaterial(material(MAT_DIELECTRIC, glm::vec3(1.0f), 0.0f, 1.5f));
        for (float cosTheta : {-0.9f, -0.5f}) {
            const glm::vec3 wo = directionWithCos(cosTheta);
            CHECK(furnace(h.sample(wo, n), wo, 1.5f) == Approx(1.0).margin(1e-5));
        }
    }
    SECTION("rough conductors with F = 1 lose what single-scattering GGX loses; compensation restores it") {
        // Normal incidence: E(1, alpha) = 0.3069 at alpha = 1 is exact (1 - ln 2, integrated by
        // hand: D = 1/pi and G2 = 2 cos(2 theta_h) / (1 + cos(2 theta_h)) there). The numbers the
        // issue quotes (0.973 / 0.845 / 0.628 / 0.406 height-correlated) are the cosine-weighted
        // averages over wo, E_avg = 2 int E(mu) mu dmu, checked below.
        const float alphas[] = {0.1f, 0.3f, 0.6f, 1.0f};
        const double reference[] = {0.9881, 0.8768, 0.5912, 0.3069};
        const double referenceAvg[] = {0.973, 0.845, 0.628, 0.406};
        GLuint tableBuffer = 0;  // the table the renderer computes (shaders/bsdf/ggx_albedo.comp)
        glCreateBuffers(1, &tableBuffer);
        std::string tableError;
        REQUIRE(computeBsdfTables(defaultShaderDir(), tableBuffer, &tableError));
        const std::vector<float> table = readFloatBuffer(tableBuffer);
        glDeleteBuffers(1, &tableBuffer);
        for (int a = 0; a < 4; ++a) {
            h.setMaterial(material(MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), alphas[a], 1.5f, MAT_FLAG_FRESNEL_ONE));
            double e = furnace(h.sample(glm::vec3(0, 0, 1), n), glm::vec3(0, 0, 1), 1.5f);
            const int j = int(std::lround(alphas[a] * (GGX_ALBEDO_TABLE_SIZE - 1)));
            std::printf("furnace rough conductor F=1 alpha %.1f normal: %.4f (reference %.3f, CPU table %.4f at alpha %.3f)\n",
                        double(alphas[a]), e, reference[a], double(table[size_t(j) * GGX_ALBEDO_TABLE_SIZE + GGX_ALBEDO_TABLE_SIZE - 1]),
                        double(j) / (GGX_ALBEDO_TABLE_SIZE - 1));
            INFO("alpha " << alphas[a]);
            CHECK(e == Approx(reference[a]).margin(0.004));
            // E_avg by the midpoint rule over mu.
            double avg = 0.0;
            const int kMu = 16;
            for (int k = 0; k < kMu; ++k) {
                const float mu = (float(k) + 0.5f) / kMu;
                const glm::vec3 wo = directionWithCos(mu);
                avg += 2.0 * furnace(h.sample(wo, 1u << 15), wo, 1.5f) * mu / kMu;
            }
            std::printf("furnace rough conductor F=1 alpha %.1f average over wo: %.4f (issue: %.3f)\n", double(alphas[a]), avg,
                        referenceAvg[a]);
            CHECK(avg == Approx(referenceAvg[a]).margin(0.01));
            h.setMaterial(material(MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), alphas[a], 1.5f,
                                   MAT_FLAG_FRESNEL_ONE | MAT_FLAG_ENERGY_COMPENSATION));
            for (float cosTheta : cosines) {
                const glm::vec3 wo = directionWithCos(cosTheta);
                double ec = furnace(h.sample(wo, n), wo, 1.5f);
                std::printf("furnace rough conductor F=1 compensated alpha %.1f cos %.2f: %.4f\n", double(alphas[a]),
                            double(cosTheta), ec);
                INFO("compensated, cos " << cosTheta);
                CHECK(ec == Approx(1.0).margin(0.015));
            }
        }
    }
    SECTION("lossy models stay at or below 1") {
        struct Case { const char* name; gpu::GpuMaterial mat; };
        const Case cases[] = {
            {"oren-nayar sigma 0.5", material(MAT_OREN_NAYAR, glm::vec3(1.0f), 0.5f)},
            {"oren-nayar sigma 1.0", material(MAT_OREN_NAYAR, glm::vec3(1.0f), 1.0f)},
            {"rough glass a=0.3", material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.3f, 1.5f)},
            {"rough glass a=0.8", material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.8f, 1.5f)},
            {"rough transmission a=0.3", material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.3f, 1.5f, MAT_FLAG_NO_REFLECTION)},
            {"gold a=0.3", material(MAT_ROUGH_CONDUCTOR, glm::vec3(1.0f), 0.3f)},
        };
        for (const Case& c : cases) {
            h.setMaterial(c.mat);
            for (float cosTheta : cosines) {
                const glm::vec3 wo = directionWithCos(cosTheta);
                double e = furnace(h.sample(wo, n), wo, c.mat.params.y);
                std::printf("furnace %-32s cos %.2f: %.4f\n", c.name, double(cosTheta), e);
                INFO(c.name << " cos " << cosTheta);
                CHECK(e <= 1.003);
                CHECK(e > 0.3);
            }
        }
        // Rough transmission alone keeps what glass reflects: nearly lossless when nearly smooth
        // (glass of the same roughness reflects F = 0.04 at normal incidence), and every sample
        // crosses the surface from outside (no reflection lobe where light can refract).
        {
            const glm::vec3 wo(0, 0, 1);
            h.setMaterial(material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.01f, 1.5f, MAT_FLAG_NO_REFLECTION));
            const Harness::Samples t = h.sample(wo, n);
            CHECK(furnace(t, wo, 1.5f) == Approx(1.0).margin(0.003));
            size_t reflected = 0;
            for (size_t i = 0; i < t.wi.size(); ++i) reflected += t.pdf[i] > 0.0f && t.wi[i].z > 0.0f;
            CHECK(reflected == 0);
            h.setMaterial(material(MAT_ROUGH_DIELECTRIC, glm::vec3(1.0f), 0.01f, 1.5f));
            CHECK(furnace(h.sample(wo, n), wo, 1.5f) == Approx(1.0).margin(0.003));  // glass: R + T
        }
        // Oren-Nayar, plain and compensated, against its albedo integrated from the formula. The
        // compensated one is not bounded by 1 (docs/materials.md): it over-brightens grazing
        // views, which is checked as a fact of the model, not as a loss of energy.
        for (float sigma : {0.5f, 1.0f}) {
            for (bool compensated : {false, true}) {
                h.setMaterial(material(MAT_OREN_NAYAR, glm::vec3(1.0f), sigma, 1.5f,
                                       compensated ? MAT_FLAG_ENERGY_COMPENSATION : 0u));
                for (float cosTheta : cosines) {
                    const glm::vec3 wo = directionWithCos(cosTheta);
                    const double e = furnace(h.sample(wo, n), wo, 1.5f);
                    const double expected = orenNayarAlbedo(sigma, cosTheta, compensated);
                    std::printf("furnace oren-nayar%s sigma %.1f cos %.2f: %.4f (quadrature %.4f)\n",
                                compensated ? " compensated" : "", double(sigma), double(cosTheta), e, expected);
                    INFO("oren-nayar sigma " << sigma << (compensated ? " compensated" : "") << " cos " << cosTheta);
                    CHECK(e == Approx(expected).epsilon(0.005));
                }
            }
        }
        CHECK(orenNayarAlbedo(0.5, 0.1, true) > 1.1);  // the compensation overshoots at grazing views
        CHECK(orenNayarAlbedo(0.5, 1.0, false) == Approx(1.0 - 0.25 / (2.0 * 0.58)).epsilon(1e-4));  // = A at normal incidence
    }
}

TEST_CASE("smooth dielectric: reflects with probability F, refracts by Snell's law", "[gpu][bsdf]") {
    Harness& h = harness();
    const float eta = 1.5f;
    h.setMaterial(material(MAT_DIELECTRIC, glm::vec3(1.0f), 0.0f, eta));
    for (float cosTheta : {1.0f, 0.5f, 0.05f, -0.9f, -0.5f}) {
        INFO("cos " << cosTheta);
        const glm::vec3 wo = directionWithCos(cosTheta);
        // Fresnel in double, written independently of the GLSL.
        double ci = std::abs(cosTheta), e = cosTheta > 0 ? eta : 1.0 / eta;
        double s2t = (1.0 - ci * ci) / (e * e);
        double F = 1.0;
        if (s2t < 1.0) {
            double ct = std::sqrt(1.0 - s2t);
            double rs = (ci - e * ct) / (ci + e * ct), rp = (e * ci - ct) / (e * ci + ct);
            F = 0.5 * (rs * rs + rp * rp);
        }
        const GLuint n = 1u << 16;
        Harness::Samples s = h.sample(wo, n);
        double reflected = 0.0;
        for (size_t i = 0; i < n; ++i) {
            REQUIRE(s.pdf[i] > 0.0f);
            REQUIRE((s.flags[i] & 1u) != 0u);  // delta
            CHECK(s.eval[i] == glm::vec3(0.0f));
            CHECK(s.pdfEval[i] == 0.0f);
            if (s.flags[i] & 2u) {
                // Snell: e sin(theta_t) = sin(theta_i) (relative to the side), opposite azimuth.
                double st = std::sqrt(std::max(0.0, 1.0 - double(s.wi[i].z) * s.wi[i].z));
                CHECK(st * e == Approx(std::sqrt(1.0 - ci * ci)).margin(1e-4));
                CHECK(s.wi[i].z * wo.z < 0.0f);
                CHECK(s.wi[i].x * wo.x <= 0.0f);
            } else {
                reflected += 1.0;
                CHECK(s.wi[i].x == Approx(-wo.x).margin(1e-6));
                CHECK(s.wi[i].z == Approx(wo.z).margin(1e-6));
            }
        }
        const double sd = std::sqrt(F * (1.0 - F) / n);
        CHECK(reflected / n == Approx(F).margin(5.0 * sd + 1e-6));
    }
}

TEST_CASE("surface material white furnace: never above 1, and 1 where nothing absorbs", "[gpu][bsdf][furnace]") {
    // Tolerance: a white base under the specular layer reflects 1 up to the albedo table's error
    // (its E(wo) against the true one; the table test measures < 1.4e-3) and the sampling noise
    // (2^17 samples), so 0.005; a coat and a white sheen over it reflect w E(wo) + (1 - w E(wo))
    // times that, so the same 0.005; no configuration may exceed 1 by more than 0.005.
    Harness& h = harness();
    const GLuint n = 1u << 17;
    const float cosines[] = {1.0f, 0.5f, 0.1f};
    auto albedo = [&](const SurfaceParams& p, float cosTheta) {
        h.setMaterial(surface(p));
        const glm::vec3 wo = directionWithCos(cosTheta);
        return furnace(h.sample(wo, n), wo, 1.5f);
    };
    for (float alpha : {0.05f, 0.3f, 0.8f}) {
        for (float ior : {1.3f, 1.5f, 2.2f}) {
            SurfaceParams white;
            white.specAlpha = alpha;
            white.specIor = ior;
            for (float c : cosines) {
                const double e = albedo(white, c);
                std::printf("furnace surface white base + specular alpha %.2f ior %.1f cos %.2f: %.4f\n", double(alpha),
                            double(ior), double(c), e);
                INFO("specular alpha " << alpha << " ior " << ior << " cos " << c);
                CHECK(e == Approx(1.0).margin(0.005));
            }
        }
        SurfaceParams coated;
        coated.specAlpha = 0.3f;
        coated.coatWeight = 1.0f;
        coated.coatAlpha = alpha;
        SurfaceParams fuzzy = coated;
        fuzzy.sheen = glm::vec3(1.0f);
        fuzzy.sheenRoughness = alpha;
        for (float c : cosines) {
            const double ec = albedo(coated, c), es = albedo(fuzzy, c);
            std::printf("furnace surface white + coat alpha %.2f cos %.2f: %.4f; + white sheen r %.2f: %.4f\n",
                        double(alpha), double(c), ec, double(alpha), es);
            INFO("coat alpha " << alpha << " cos " << c);
            CHECK(ec == Approx(1.0).margin(0.005));
            CHECK(es == Approx(1.0).margin(0.005));
        }
    }
    // Metal with F0 = 1 (white base, white edge): single-scattering GGX, so at most 1 and exactly
    // the F = 1 conductor's albedo at normal incidence (0.9881 at alpha 0.1, tested above).
    {
        SurfaceParams metal;
        metal.metalness = 1.0f;
        metal.specAlpha = 0.1f;
        h.setMaterial(surface(metal));
        const double e = furnace(h.sample(glm::vec3(0, 0, 1), n), glm::vec3(0, 0, 1), 1.5f);
        CHECK(e == Approx(0.9881).margin(0.004));
    }
    // Random configurations (fixed seed): never above 1.
    std::uint32_t state = 12345u;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / 16777216.0f;
    };
    double worst = 0.0;
    for (int k = 0; k < 12; ++k) {
        SurfaceParams p;
        p.base = glm::vec3(next(), next(), next());
        p.metalness = next() < 0.3f ? 1.0f : next();
        p.specWeight = next();
        p.specAlpha = 0.02f + next();
        p.specIor = 1.0f + 2.0f * next();
        p.specColor = glm::vec3(next(), next(), next());
        p.coatWeight = next() < 0.5f ? 0.0f : next();
        p.coatAlpha = 0.02f + next();
        p.coatIor = 1.0f + 2.0f * next();
        p.coatColor = glm::vec3(next(), next(), next());
        p.sheen = next() < 0.5f ? glm::vec3(0.0f) : glm::vec3(next(), next(), next());
        p.sheenRoughness = next();
        for (float c : cosines) {
            const double e = albedo(p, c);
            worst = std::max(worst, e);
            INFO("random configuration " << k << " cos " << c);
            CHECK(e <= 1.005);
        }
    }
    std::printf("furnace surface, 12 random configurations: largest albedo %.4f\n", worst);
}
