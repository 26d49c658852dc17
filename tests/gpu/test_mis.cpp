// Multiple importance sampling: light sampling alone, BSDF sampling alone and their MIS
// combination are three estimators of the same integral, so for every light type they must agree
// (per image block, within statistical error); and MIS must not be worse than the better of the
// two where one of them is poor (Veach 1997, ch. 9).
#include "tests/gpu/gl_fixture.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

namespace {

constexpr int kSize = 24, kBlocks = 4;

struct BlockStats { glm::dvec3 mean[kBlocks][kBlocks]; glm::dvec3 var[kBlocks][kBlocks]; double totalVariance = 0; };

BlockStats blocks(const Film& f) {
    BlockStats b{};
    const int bs = kSize / kBlocks;
    const double n = bs * bs;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            size_t i = f.index(x, y);
            b.mean[y / bs][x / bs] += glm::dvec3(f.mean[i]) / n;
            b.var[y / bs][x / bs] += glm::dvec3(f.varianceOfMean[i]) / (n * n);
            b.totalVariance += glm::dot(glm::dvec3(f.varianceOfMean[i]), glm::dvec3(1.0));
        }
    return b;
}

// A grey floor seen at an angle, a grey ball on it, and the light(s) under test.
Scene floorScene() {
    Scene s;
    s.render.width = s.render.height = kSize;
    s.render.maxDepth = 3;
    s.render.seed = 3;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.6f, 0.5f, 0.4f), glm::vec3(0.0f)});
    s.objects.push_back(test::floorQuad("grey", 4.0f));
    s.objects.push_back(test::sphereAt("grey", glm::vec3(0.3f, 0.4f, 0.0f), 0.4f));
    s.camera.position = glm::vec3(0.0f, 2.0f, 3.0f);
    s.camera.lookAt = glm::vec3(0.0f, 0.0f, 0.0f);
    s.camera.fovDegrees = 50.0f;
    return s;
}

// An emissive box (material "glow", the given diffuse albedo) standing on the floor.
void addGlowingBox(Scene& s, float albedo) {
    s.materials.push_back({"glow", MaterialType::Diffuse, glm::vec3(albedo), glm::vec3(3.0f, 2.0f, 1.0f)});
    Object box;
    box.shape = Shape::Box;
    box.material = "glow";
    box.transform.translate = glm::vec3(-0.8f, 0.3f, -0.5f);
    box.transform.scale = glm::vec3(0.2f, 0.3f, 0.2f);
    s.objects.push_back(box);
}

struct Renders { Film mis, light, bsdf; };

Renders renderAll(Renderer& r, const Scene& s, int spp, int bsdfSppFactor = 4) {
    Renders out;
    r.setStrategy(STRATEGY_MIS);
    out.mis = test::renderFilm(r, s, spp);
    r.setStrategy(STRATEGY_LIGHT_ONLY);
    out.light = test::renderFilm(r, s, spp);
    // BSDF sampling finds small lights rarely: give it more samples, or a block whose samples
    // all missed the light would report a mean of 0 with a standard error of 0.
    r.setStrategy(STRATEGY_BSDF_ONLY);
    out.bsdf = test::renderFilm(r, s, bsdfSppFactor * spp);
    r.setStrategy(STRATEGY_MIS);
    return out;
}

void checkAgree(const Film& a, const Film& b, const char* what) {
    BlockStats sa = blocks(a), sb = blocks(b);
    int disagreements = 0;
    for (int by = 0; by < kBlocks; ++by)
        for (int bx = 0; bx < kBlocks; ++bx)
            for (int c = 0; c < 3; ++c) {
                double diff = std::abs(sa.mean[by][bx][c] - sb.mean[by][bx][c]);
                double se = std::sqrt(sa.var[by][bx][c] + sb.var[by][bx][c]);
                if (diff > 4.0 * se + 1e-6) {
                    ++disagreements;
                    UNSCOPED_INFO(what << ": block (" << bx << ", " << by << ") channel " << c << ": "
                                       << sa.mean[by][bx][c] << " vs " << sb.mean[by][bx][c] << ", combined se " << se);
                }
            }
    CHECK(disagreements == 0);
}

void checkConsistent(const Renders& r) {
    checkAgree(r.mis, r.light, "MIS vs light sampling");
    checkAgree(r.mis, r.bsdf, "MIS vs BSDF sampling");
}

}  // namespace

TEST_CASE("MIS, light sampling and BSDF sampling agree for every light type", "[gpu][mis]") {
    auto renderer = test::makeRenderer();
    SECTION("rectangle light, one-sided") {
        Scene s = floorScene();
        Light l;
        l.type = LightType::Rect;
        l.color = glm::vec3(4.0f);
        l.transform.translate = glm::vec3(-0.5f, 1.5f, 0.0f);
        l.transform.rotate = glm::vec3(90.0f, 0.0f, 0.0f);
        l.transform.scale = glm::vec3(0.8f, 0.5f, 1.0f);
        s.lights.push_back(l);
        checkConsistent(renderAll(*renderer, s, 64));
    }
    SECTION("sphere light") {
        Scene s = floorScene();
        Light l;
        l.type = LightType::Sphere;
        // Large enough that BSDF sampling hits it from every block: the standard errors come from
        // the samples, and an estimator that never saw the light would report zero error.
        l.color = glm::vec3(2.0f);
        l.position = glm::vec3(-0.6f, 1.5f, 0.4f);
        l.radius = 0.6f;
        s.lights.push_back(l);
        checkConsistent(renderAll(*renderer, s, 128));
    }
    SECTION("emissive object (a box) and the sky together") {
        Scene s = floorScene();
        addGlowingBox(s, 0.5f);
        s.environment.type = EnvironmentType::Sky;
        s.environment.intensity = 0.5f;
        checkConsistent(renderAll(*renderer, s, 64));
    }
    SECTION("emissive mesh (a torus)") {
        test::TempDir dir;
        test::writeObjTorus(dir.file("torus.obj"), 1.0, 0.35, 32, 16);
        Scene s = floorScene();
        s.materials.push_back({"glow", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(2.0f, 1.5f, 1.0f)});
        Object torus;
        torus.shape = Shape::Mesh;
        torus.file = dir.file("torus.obj");
        torus.material = "glow";
        torus.transform.translate = glm::vec3(-0.6f, 1.3f, 0.0f);
        torus.transform.rotate = glm::vec3(70.0f, 0.0f, 0.0f);
        torus.transform.scale = glm::vec3(0.5f);
        s.objects.push_back(torus);
        checkConsistent(renderAll(*renderer, s, 64));
    }
    SECTION("the light tree, power and uniform selection give the same image") {
        Scene s = floorScene();
        Light a;
        a.type = LightType::Sphere;
        a.color = glm::vec3(20.0f);
        a.position = glm::vec3(-0.6f, 1.2f, 0.4f);
        a.radius = 0.1f;
        Light b = a;
        b.color = glm::vec3(1.0f);
        b.position = glm::vec3(0.8f, 1.0f, -0.3f);
        s.lights = {a, b};
        renderer->setStrategy(STRATEGY_MIS);
        s.render.lightSelection = LightSelection::Tree;
        Film tree = test::renderFilm(*renderer, s, 64);
        s.render.lightSelection = LightSelection::Power;
        Film byPower = test::renderFilm(*renderer, s, 64);
        s.render.lightSelection = LightSelection::Uniform;
        Film uniform = test::renderFilm(*renderer, s, 64);
        checkAgree(byPower, uniform, "power vs uniform selection");
        checkAgree(tree, uniform, "tree vs uniform selection");
        // The dim light gets 1/2 of the samples instead of 1/21: more noise overall.
        CHECK(blocks(byPower).totalVariance < blocks(uniform).totalVariance);
        CHECK(blocks(tree).totalVariance < blocks(uniform).totalVariance);
    }
    SECTION("many lights of every kind and an environment, chosen by the light tree") {
        Scene s = floorScene();
        addGlowingBox(s, 0.3f);
        for (int i = 0; i < 6; ++i) {
            Light l;
            l.type = LightType::Sphere;
            const float fi = float(i);
            l.color = glm::vec3(1.0f + fi, 2.0f, 3.0f - 0.4f * fi);
            l.position = glm::vec3(-1.2f + 0.5f * fi, 1.0f + 0.1f * fi, -0.5f + 0.2f * fi);
            l.radius = 0.3f;
            s.lights.push_back(l);
        }
        Light rect;
        rect.type = LightType::Rect;
        rect.color = glm::vec3(3.0f);
        rect.transform.translate = glm::vec3(0.8f, 1.4f, 0.6f);
        rect.transform.rotate = glm::vec3(100.0f, 20.0f, 0.0f);
        rect.transform.scale = glm::vec3(0.4f, 0.3f, 1.0f);
        s.lights.push_back(rect);
        // Two emissive meshes: each light's own triangle table (GpuLight::info.w) beside its
        // path in the tree (GpuLight::tree.x).
        test::TempDir dir;
        test::writeObjTorus(dir.file("torus.obj"), 1.0, 0.35, 16, 8);
        for (int i = 0; i < 2; ++i) {
            Object torus;
            torus.shape = Shape::Mesh;
            torus.file = dir.file("torus.obj");
            torus.material = "glow";
            torus.transform.translate = glm::vec3(i == 0 ? -0.9f : 0.9f, 1.2f, -0.8f);
            torus.transform.rotate = glm::vec3(60.0f, 0.0f, 0.0f);
            torus.transform.scale = i == 0 ? glm::vec3(0.25f) : glm::vec3(0.2f, 0.3f, 0.45f);
            s.objects.push_back(torus);
        }
        s.environment.type = EnvironmentType::Sky;
        s.environment.intensity = 0.3f;
        s.render.lightSelection = LightSelection::Tree;
        checkConsistent(renderAll(*renderer, s, 64));
    }
}

TEST_CASE("MIS is close to the better strategy where the other one is poor", "[gpu][mis]") {
    auto renderer = test::makeRenderer();
    SECTION("a small bright sphere light: BSDF sampling rarely hits it") {
        Scene s = floorScene();
        Light l;
        l.type = LightType::Sphere;
        l.color = glm::vec3(200.0f);
        // Above the top of the view, so no pixel sees the light itself (its edge pixels would
        // dominate every strategy's variance alike).
        l.position = glm::vec3(0.0f, 2.3f, 2.0f);
        l.radius = 0.05f;
        s.lights.push_back(l);
        s.render.maxDepth = 1;
        Renders r = renderAll(*renderer, s, 32, 1);  // equal sample counts: variances comparable
        double mis = blocks(r.mis).totalVariance, light = blocks(r.light).totalVariance, bsdf = blocks(r.bsdf).totalVariance;
        INFO("variance: MIS " << mis << ", light " << light << ", BSDF " << bsdf);
        CHECK(mis < 0.2 * bsdf);
        CHECK(mis < 1.3 * light);
    }
    SECTION("a uniform environment: light sampling wastes half its samples below the horizon") {
        Scene s = floorScene();
        s.environment.type = EnvironmentType::Constant;
        s.environment.radiance = glm::vec3(1.0f);
        s.render.maxDepth = 1;
        Renders r = renderAll(*renderer, s, 32, 1);  // equal sample counts: variances comparable
        double mis = blocks(r.mis).totalVariance, light = blocks(r.light).totalVariance, bsdf = blocks(r.bsdf).totalVariance;
        INFO("variance: MIS " << mis << ", light " << light << ", BSDF " << bsdf);
        // Cosine sampling is the perfect strategy here (its weight is the albedo); the power
        // heuristic gives up a little of that for robustness, but stays far from light sampling.
        CHECK(mis < 0.25 * light);
        CHECK(mis < 3.0 * bsdf);
    }
}
