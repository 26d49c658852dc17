// One camera (renderer/camera.h): the rays the shader shoots (integrator/camera.glsl, through the
// frame makeFrame rounds) are the editor's picking rays (editor/model/viewport_math.cpp), with
// roll, non-square images and every fov axis; what the editor picks under a pixel is what the
// renderer's primary ray hits there; and a focus point set by picking (Shift+click) is where
// every lens ray of that pixel converges. Issue 14: the editor's copy of the camera ignored roll,
// so picking, focus and the gizmo were wrong on a rolled camera.
#include "tests/gpu/gl_fixture.h"

#include "editor/model/viewport_math.h"
#include "renderer/camera.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <tuple>
#include <vector>

using namespace caustic;

namespace {

struct GpuRay { glm::vec3 origin; float t; glm::vec3 direction; };

// inputs: (pixel x, pixel y, lens u, lens v) per ray.
std::vector<GpuRay> shootOnGpu(Renderer& r, const std::vector<glm::vec4>& inputs) {
    GLuint buffers[2];
    glCreateBuffers(2, buffers);
    glNamedBufferData(buffers[0], GLsizeiptr(inputs.size() * sizeof(glm::vec4)), inputs.data(), GL_STATIC_DRAW);
    glNamedBufferData(buffers[1], GLsizeiptr(2 * inputs.size() * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    const GLuint program = test::kernel("camera_rays.comp");
    r.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, buffers[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, buffers[1]);
    glUseProgram(program);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_count"), GLuint(inputs.size()));
    glDispatchCompute(GLuint((inputs.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> out(2 * inputs.size());
    glGetNamedBufferSubData(buffers[1], 0, GLsizeiptr(out.size() * sizeof(glm::vec4)), out.data());
    glDeleteBuffers(2, buffers);
    REQUIRE(glDebugErrorCount() == 0);
    std::vector<GpuRay> rays;
    for (size_t i = 0; i < inputs.size(); ++i)
        rays.push_back({glm::vec3(out[2 * i]), out[2 * i].w, glm::vec3(out[2 * i + 1])});
    return rays;
}

// A sphere, a box and a floor quad in front of the camera, nothing behind it.
Scene pickingScene(int w, int h, float roll, FovAxis axis) {
    Scene s;
    s.render.width = w;
    s.render.height = h;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(0.0f)});
    s.objects.push_back(test::floorQuad("grey", 2.0f));
    s.objects.push_back(test::sphereAt("grey", glm::vec3(-0.5f, 0.5f, 0.0f), 0.5f));
    Object box;
    box.shape = Shape::Box;
    box.material = "grey";
    box.transform.translate = glm::vec3(0.7f, 0.4f, -0.3f);
    box.transform.rotate = glm::vec3(0.0f, 30.0f, 0.0f);
    box.transform.scale = glm::vec3(0.4f);
    s.objects.push_back(box);
    s.camera.position = glm::vec3(0.4f, 1.6f, 3.5f);
    s.camera.lookAt = glm::vec3(0.0f, 0.4f, 0.0f);
    s.camera.fovDegrees = 45.0f;
    s.camera.fovAxis = axis;
    s.camera.rollDegrees = roll;
    return s;
}

double lineDistance(glm::dvec3 origin, glm::dvec3 dir, glm::dvec3 p) {
    const glm::dvec3 d = glm::normalize(dir);
    const glm::dvec3 v = p - origin;
    return glm::length(v - glm::dot(v, d) * d);
}

}  // namespace

TEST_CASE("one camera: the shader's rays are the editor's picking rays, and picking agrees with the renderer's hits",
          "[gpu][camera][editor]") {
    auto renderer = test::makeRenderer();
    int cases = 0, hits = 0;
    for (auto [w, h] : {std::pair{200, 100}, std::pair{100, 200}})
        for (float roll : {0.0f, 30.0f, -115.0f})
            for (FovAxis axis : {FovAxis::X, FovAxis::Y, FovAxis::Smaller, FovAxis::Larger}) {
                const Scene s = pickingScene(w, h, roll, axis);
                std::string error;
                REQUIRE(renderer->setScene(s, &error));
                std::vector<glm::vec4> inputs;
                for (int y = 0; y < h; y += 7)
                    for (int x = 0; x < w; x += 7) inputs.push_back(glm::vec4(float(x), float(y), 0.5f, 0.5f));
                const std::vector<GpuRay> gpu = shootOnGpu(*renderer, inputs);
                int dirMismatch = 0, pickMismatch = 0, tMismatch = 0;
                for (size_t i = 0; i < inputs.size(); ++i) {
                    const glm::vec2 pixel = glm::vec2(inputs[i]) + 0.5f;  // the box filter's centre sample
                    const editor::Ray ray = editor::cameraRay(s.camera, w, h, pixel);
                    if (glm::length(ray.direction - gpu[i].direction) > 2e-6f || glm::length(ray.origin - gpu[i].origin) > 1e-6f)
                        ++dirMismatch;
                    const std::optional<editor::PickHit> picked = editor::pick(s, ray);
                    const bool gpuHit = gpu[i].t >= 0.0f;
                    hits += gpuHit;
                    if (picked.has_value() != gpuHit) ++pickMismatch;
                    else if (gpuHit && std::abs(picked->distance - gpu[i].t) > 1e-4f * gpu[i].t) ++tMismatch;
                }
                INFO(w << "x" << h << ", roll " << roll << ", fov axis " << int(axis) << ": " << inputs.size()
                       << " rays, direction mismatches " << dirMismatch << ", pick/hit mismatches " << pickMismatch
                       << ", distance mismatches " << tMismatch);
                CHECK(dirMismatch == 0);
                // A ray grazing an edge may be decided differently by the two arithmetics.
                CHECK(pickMismatch <= 1);
                CHECK(tMismatch == 0);
                ++cases;
            }
    CHECK(cases == 24);
    CHECK(hits > 24 * 100);  // the objects fill a good part of every view

    // Roll turns the image: the same pixel looks elsewhere (the editor's old copy missed this).
    const Scene flat = pickingScene(200, 100, 0.0f, FovAxis::X), rolled = pickingScene(200, 100, 30.0f, FovAxis::X);
    const glm::vec3 a = editor::cameraRay(flat.camera, 200, 100, {20.5f, 10.5f}).direction;
    const glm::vec3 b = editor::cameraRay(rolled.camera, 200, 100, {20.5f, 10.5f}).direction;
    CHECK(glm::length(a - b) > 0.1f);
}

TEST_CASE("one camera: a focus point picked in the editor is where the renderer's lens rays converge", "[gpu][camera][editor]") {
    auto renderer = test::makeRenderer();
    for (float roll : {0.0f, 30.0f}) {
        Scene s = pickingScene(160, 90, roll, FovAxis::Smaller);
        // Shift+click on a pixel of the ball (editor/ui/viewport_panel.cpp: focus on the hit point).
        const glm::vec2 pixel(60.5f, 52.5f);
        const editor::Ray ray = editor::cameraRay(s.camera, 160, 90, pixel);
        const std::optional<editor::PickHit> picked = editor::pick(s, ray);
        REQUIRE(picked.has_value());
        const glm::vec3 point = ray.origin + picked->distance * ray.direction;
        s.camera.focusPoint = point;
        s.camera.apertureRadius = 0.2f;
        s.camera.blades = 6;
        const CameraFrame frame = cameraFrame(s.camera, 160, 90);
        const glm::dvec3 focus = frame.focusOn(frame.pixelDirection(glm::dvec2(pixel), 160, 90));
        CHECK(glm::length(focus - glm::dvec3(point)) < 1e-4 * glm::length(glm::dvec3(point) - frame.position));
        std::string error;
        REQUIRE(renderer->setScene(s, &error));
        std::vector<glm::vec4> inputs;
        for (int i = 0; i < 64; ++i)
            inputs.push_back(glm::vec4(pixel - 0.5f, (float(i % 8) + 0.5f) / 8.0f, (float(i / 8) + 0.5f) / 8.0f));
        const std::vector<GpuRay> gpu = shootOnGpu(*renderer, inputs);
        double spread = 0.0, worst = 0.0;
        for (const GpuRay& g : gpu) {
            spread = std::max(spread, glm::length(glm::dvec3(g.origin) - frame.position));
            worst = std::max(worst, lineDistance(glm::dvec3(g.origin), glm::dvec3(g.direction), glm::dvec3(point)));
        }
        INFO("roll " << roll << ": lens rays start up to " << spread << " from the camera and pass within " << worst
                     << " of the picked point");
        CHECK(spread > 0.1);      // they do come from all over the lens (radius 0.2)
        CHECK(worst < 2e-4);      // and all meet at the picked point
    }
}
