// Every light's sampler, run through the real GLSL: the mean of 1/pdf over its samples equals
// the solid angle the light subtends (a pdf that integrates to one over exactly that set), each
// sampled direction reaches the light at the sampled distance, and lightPdf (used by MIS for
// BSDF-sampled hits) agrees with the sampler's own pdf.
#include "tests/gpu/gl_fixture.h"
#include "tests/support/meshes.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>

using namespace caustic;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSamples = 1 << 16;

// Solid angle of the triangle (a, b, c) seen from the origin: Van Oosterom and Strackee 1983,
// tan(omega / 2) = |a . (b x c)| / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|).
double triangleSolidAngle(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    double num = std::abs(glm::dot(a, glm::cross(b, c)));
    double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    double w = 2.0 * std::atan2(num, den);
    return w < 0 ? w + 2.0 * kPi : w;
}

struct SamplerStats { double meanInvPdf = 0, standardError = 0, maxPdfMismatch = 0, hitFraction = 0; int valid = 0; };

SamplerStats runSampler(Renderer& renderer, const Scene& scene, glm::vec3 point, unsigned light = 0) {
    std::string error;
    REQUIRE(renderer.setScene(scene, &error));
    const GLuint program = test::kernel("light_sampling.comp");
    GLuint out = 0;
    glCreateBuffers(1, &out);
    glNamedBufferData(out, kSamples * sizeof(glm::vec4), nullptr, GL_DYNAMIC_READ);
    renderer.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, out);
    glUseProgram(program);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_light"), light);
    glProgramUniform3fv(program, glGetUniformLocation(program, "u_point"), 1, glm::value_ptr(point));
    glDispatchCompute(kSamples / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> results(kSamples);
    glGetNamedBufferSubData(out, 0, kSamples * sizeof(glm::vec4), results.data());
    glDeleteBuffers(1, &out);
    REQUIRE(glDebugErrorCount() == 0);
    SamplerStats st;
    double sum = 0, sumSq = 0, hits = 0;
    for (const glm::vec4& r : results) {
        sum += r.x;
        sumSq += double(r.x) * r.x;
        if (r.w > 0) {
            ++st.valid;
            hits += r.z;
            st.maxPdfMismatch = std::max(st.maxPdfMismatch, double(r.y));
        }
    }
    st.meanInvPdf = sum / kSamples;
    st.standardError = std::sqrt(std::max(0.0, sumSq / kSamples - st.meanInvPdf * st.meanInvPdf) / (kSamples - 1));
    st.hitFraction = st.valid ? hits / st.valid : 0;
    return st;
}

void checkSolidAngle(const SamplerStats& st, double expected) {
    INFO("mean 1/pdf " << st.meanInvPdf << " +- " << st.standardError << ", expected solid angle " << expected
                       << "; valid " << st.valid << ", hit fraction " << st.hitFraction
                       << ", max pdf mismatch " << st.maxPdfMismatch);
    CHECK(std::abs(st.meanInvPdf - expected) <= 4.0 * st.standardError + 1e-4 * expected);
    if (expected > 0) {
        CHECK(st.hitFraction > 0.999);
        CHECK(st.maxPdfMismatch < 2e-3);
    } else {
        CHECK(st.valid == 0);
    }
}

Scene lightOnly(Light light) {
    Scene s;
    s.render.width = s.render.height = 1;
    s.lights.push_back(light);
    return s;
}

}  // namespace

TEST_CASE("rectangle light: mean 1/pdf is the solid angle, one- and two-sided", "[gpu][lights]") {
    auto renderer = test::makeRenderer();
    Light rect;
    rect.type = LightType::Rect;
    rect.transform.translate = glm::vec3(0.2f, -0.1f, 0.0f);
    rect.transform.rotate = glm::vec3(10.0f, -20.0f, 5.0f);
    rect.transform.scale = glm::vec3(0.5f, 0.3f, 1.0f);
    const glm::dmat4 m = rect.transform.toMatrix();
    auto corner = [&](double x, double y) { return glm::dvec3(m * glm::dvec4(x, y, 0, 1)); };
    const glm::dvec3 front = glm::normalize(glm::dvec3(m * glm::dvec4(0, 0, 1, 0)));
    for (glm::dvec3 p : {glm::dvec3(0, 0, 1), glm::dvec3(0.9, -0.6, 0.5), glm::dvec3(0.3, 0.2, 0.05)}) {
        auto rel = [&](glm::dvec3 c) { return c - p; };
        double omega = triangleSolidAngle(rel(corner(-1, -1)), rel(corner(1, -1)), rel(corner(1, 1))) +
                       triangleSolidAngle(rel(corner(-1, -1)), rel(corner(1, 1)), rel(corner(-1, 1)));
        const bool inFront = glm::dot(p - corner(0, 0), front) > 0;
        INFO("point " << p.x << " " << p.y << " " << p.z << (inFront ? " in front" : " behind"));
        rect.twoSided = false;
        checkSolidAngle(runSampler(*renderer, lightOnly(rect), glm::vec3(p)), inFront ? omega : 0.0);
        rect.twoSided = true;
        checkSolidAngle(runSampler(*renderer, lightOnly(rect), glm::vec3(p)), omega);
    }
}

TEST_CASE("sphere light: the cone from outside, the whole sphere of directions from inside", "[gpu][lights]") {
    auto renderer = test::makeRenderer();
    Light sphere;
    sphere.type = LightType::Sphere;
    sphere.position = glm::vec3(0.5f, 0.0f, -0.25f);
    sphere.radius = 0.5f;
    for (double d : {0.6, 2.0, 300.0}) {
        INFO("distance " << d);
        glm::vec3 p = sphere.position + glm::vec3(0.0f, float(d), 0.0f);
        double sin2 = 0.25 / (d * d);
        // 2 pi (1 - cos theta_max), with 1 - cos written to avoid cancellation for far spheres.
        double omega = 2.0 * kPi * sin2 / (1.0 + std::sqrt(1.0 - sin2));
        SamplerStats st = runSampler(*renderer, lightOnly(sphere), p);
        checkSolidAngle(st, omega);
    }
    SamplerStats inside = runSampler(*renderer, lightOnly(sphere), sphere.position + glm::vec3(0.1f, -0.2f, 0.15f));
    checkSolidAngle(inside, 4.0 * kPi);
}

TEST_CASE("environment light: mean 1/pdf is 4 pi", "[gpu][lights]") {
    auto renderer = test::makeRenderer();
    Scene s;
    s.render.width = s.render.height = 1;
    s.environment.type = EnvironmentType::Sky;
    SamplerStats st = runSampler(*renderer, s, glm::vec3(0.0f));
    checkSolidAngle(st, 4.0 * kPi);
}

TEST_CASE("emissive mesh: mean 1/pdf is the solid angle it subtends, both faces", "[gpu][lights]") {
    // A quad mesh of two triangles with an emissive material: sampled by area over its
    // triangles, so the mean of 1/pdf is the quad's solid angle, from either side.
    auto renderer = test::makeRenderer();
    test::TempDir dir;
    test::writeObjQuad(dir.file("quad.obj"));
    Scene s;
    s.render.width = s.render.height = 1;
    s.materials.push_back({"glow", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(2.0f)});
    Object o;
    o.shape = Shape::Mesh;
    o.file = dir.file("quad.obj");
    o.material = "glow";
    o.transform.translate = glm::vec3(0.1f, 0.2f, -0.3f);
    o.transform.rotate = glm::vec3(30.0f, -15.0f, 10.0f);
    o.transform.scale = glm::vec3(0.6f, 0.4f, 1.0f);
    s.objects.push_back(o);
    const glm::dmat4 m = o.transform.toMatrix();
    auto corner = [&](double x, double y) { return glm::dvec3(m * glm::dvec4(x, y, 0, 1)); };
    for (glm::dvec3 p : {glm::dvec3(0.2, 0.1, 1.0), glm::dvec3(-0.4, 0.5, -1.2)}) {
        auto rel = [&](glm::dvec3 c) { return c - p; };
        double omega = triangleSolidAngle(rel(corner(-1, -1)), rel(corner(1, -1)), rel(corner(1, 1))) +
                       triangleSolidAngle(rel(corner(-1, -1)), rel(corner(1, 1)), rel(corner(-1, 1)));
        INFO("point " << p.x << " " << p.y << " " << p.z);
        SamplerStats st = runSampler(*renderer, s, glm::vec3(p));
        checkSolidAngle(st, omega);
        // The same quad as the second of two emissive meshes (after a torus): each mesh light
        // reads its own triangle table (GpuLight::info.w), whatever its place in the light tree.
        Scene two = s;
        test::writeObjTorus(dir.file("torus.obj"), 1.0, 0.35, 12, 6);
        Object torus;
        torus.shape = Shape::Mesh;
        torus.file = dir.file("torus.obj");
        torus.material = "glow";
        torus.transform.translate = glm::vec3(5.0f, 0.0f, 0.0f);
        two.objects.insert(two.objects.begin(), torus);
        SamplerStats second = runSampler(*renderer, two, glm::vec3(p), 1);
        checkSolidAngle(second, omega);
    }
}

TEST_CASE("spot lights: the falloff follows the analytic curve in the angle, to the edge", "[gpu][lights]") {
    // A spot at the origin pointing down (inner 20 degrees, outer 35), intensity 1, seen from
    // points at distance 1 at angles 0-40 degrees from its axis: Li is the falloff itself,
    // linear in the angle (Mitsuba's) or smoothstep in the cosine, computed here in double.
    auto renderer = test::makeRenderer();
    const double inner = 20.0, outer = 35.0;
    constexpr int n = 4096;
    for (const SpotFalloff falloff : {SpotFalloff::LinearAngle, SpotFalloff::Smoothstep}) {
        Scene s;
        s.render.width = s.render.height = 8;
        Light spot;
        spot.type = LightType::Spot;
        spot.innerAngle = float(inner);
        spot.outerAngle = float(outer);
        spot.falloff = falloff;
        s.lights.push_back(spot);
        std::string error;
        REQUIRE(renderer->setScene(s, &error));
        std::vector<glm::vec4> points(n);
        for (int i = 0; i < n; ++i) {
            const double theta = glm::radians(40.0 * (i + 0.5) / n);
            points[i] = glm::vec4(float(std::sin(theta)), float(-std::cos(theta)), 0.0f, 0.0f);
        }
        GLuint buffer = 0;
        glCreateBuffers(1, &buffer);
        glNamedBufferData(buffer, n * sizeof(glm::vec4), points.data(), GL_DYNAMIC_READ);
        renderer->bindScene(0, 1);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, buffer);
        const GLuint program = test::kernel("spot_falloff.comp");
        glUseProgram(program);
        glProgramUniform1ui(program, glGetUniformLocation(program, "u_light"), 0u);
        glDispatchCompute(n / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<glm::vec4> li(n);
        glGetNamedBufferSubData(buffer, 0, n * sizeof(glm::vec4), li.data());
        glDeleteBuffers(1, &buffer);
        REQUIRE(glDebugErrorCount() == 0);
        double worst = 0.0, worstAt = 0.0;
        for (int i = 0; i < n; ++i) {
            // The angle of the float point the kernel got, in double.
            const glm::dvec3 p(points[i]);
            const double t = std::atan2(std::hypot(p.x, p.z), -p.y);
            double expected = 0.0;
            if (falloff == SpotFalloff::LinearAngle) {
                expected = std::clamp((glm::radians(outer) - t) / glm::radians(outer - inner), 0.0, 1.0);
            } else {
                const double c0 = std::cos(glm::radians(outer)), c1 = std::cos(glm::radians(inner));
                const double x = std::clamp((std::cos(t) - c0) / (c1 - c0), 0.0, 1.0);
                expected = x * x * (3.0 - 2.0 * x);
            }
            const double err = std::abs(double(li[i].g) - expected / glm::dot(p, p));
            if (err > worst) { worst = err; worstAt = glm::degrees(t); }
        }
        // An angle 1e-5 radians off moves the linear falloff by 4e-5 (its slope is 1 / 15 degrees).
        // Measured on llvmpipe: 5.8e-6 (the angle by atan2 of its sine and cosine), 2.3e-4 by acos.
        INFO((falloff == SpotFalloff::LinearAngle ? "linear in the angle" : "smoothstep") << ": worst error " << worst
                                                                                        << " at " << worstAt << " degrees");
        CHECK(worst < 1.5e-5);
    }
}
