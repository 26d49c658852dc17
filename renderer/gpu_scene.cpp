// compileScene: a Scene into the GPU's tables (renderer/gpu_scene.h); the order of the work
// and the analytic primitives. The builder's other parts: gpu_scene_builder.h.
#include "renderer/gpu_scene_builder.h"

namespace caustic {

namespace gpu {
// Each shared struct is its row list's size (shaders/shared/layout.h): 16 bytes a row.
#define CHECK_ROWS(Type, ROWS) static_assert(sizeof(Type) == 16 * GPU_ROW_COUNT(ROWS), #Type " is not its rows");
CHECK_ROWS(GpuPrimitive, GPU_PRIMITIVE_ROWS)
CHECK_ROWS(GpuBvhNode, GPU_BVH_NODE_ROWS)
CHECK_ROWS(GpuWideBvhNode, GPU_WIDE_BVH_NODE_ROWS)
CHECK_ROWS(GpuInstance, GPU_INSTANCE_ROWS)
CHECK_ROWS(GpuTriangle, GPU_TRIANGLE_ROWS)
CHECK_ROWS(GpuVertex, GPU_VERTEX_ROWS)
CHECK_ROWS(GpuMaterial, GPU_MATERIAL_ROWS)
CHECK_ROWS(GpuTexture, GPU_TEXTURE_ROWS)
CHECK_ROWS(GpuLight, GPU_LIGHT_ROWS)
CHECK_ROWS(GpuLightNode, GPU_LIGHT_NODE_ROWS)
CHECK_ROWS(GpuFrame, GPU_FRAME_ROWS)
#undef CHECK_ROWS
static_assert(offsetof(GpuMaterial, info) == 16 * GPU_MATERIAL_ROW_INFO &&
                  offsetof(GpuMaterial, textures) == 16 * GPU_MATERIAL_ROW_TEXTURES,
              "GPU_MATERIAL_ROW_INFO and GPU_MATERIAL_ROW_TEXTURES are not the rows of info and textures");
static_assert(sizeof(GpuBvhNode) == sizeof(caustic::BvhNode));
}  // namespace gpu

namespace scene_compile {

void Builder::growBounds(glm::vec3 p) {
    out.boundsMin = glm::min(out.boundsMin, p);
    out.boundsMax = glm::max(out.boundsMax, p);
}

std::uint32_t Builder::addQuad(const glm::mat4& m, std::uint32_t material, std::uint32_t flags) {
    gpu::GpuPrimitive p{};
    glm::vec3 corner = glm::vec3(m * glm::vec4(-1, -1, 0, 1));
    glm::vec3 eu = glm::vec3(m * glm::vec4(2, 0, 0, 0));
    glm::vec3 ev = glm::vec3(m * glm::vec4(0, 2, 0, 0));
    p.a = glm::vec4(corner, 0);
    p.b = glm::vec4(eu, 0);
    p.c = glm::vec4(ev, 0);
    p.info = glm::uvec4(PRIM_QUAD, material, 0, flags);
    Aabb box;
    for (glm::vec3 q : {corner, corner + eu, corner + ev, corner + eu + ev}) {
        growBounds(q);
        box.grow(q);
    }
    // A flat box is fine for the slab test, but give it a sliver of thickness so that
    // rounding cannot make it empty.
    const glm::vec3 pad = 1e-6f * (glm::abs(box.min) + glm::abs(box.max)) + 1e-20f;
    primBounds.push_back({box.min - pad, box.max + pad});
    out.primitives.push_back(p);
    return static_cast<std::uint32_t>(out.primitives.size() - 1);
}

std::uint32_t Builder::addSphere(const glm::mat4& m, std::uint32_t material, std::uint32_t flags) {
    glm::mat4 w2o = glm::inverse(m);
    glm::mat4 rows = glm::transpose(w2o);  // rows of w2o as columns
    gpu::GpuPrimitive p{};
    p.a = rows[0];
    p.b = rows[1];
    p.c = rows[2];
    p.info = glm::uvec4(PRIM_SPHERE, material, 0, flags);
    // Bounds of the transformed unit sphere: |row_i of the linear part| around the centre.
    glm::vec3 c = glm::vec3(m[3]);
    glm::mat3 lin(m);
    glm::vec3 ext(glm::length(glm::vec3(lin[0].x, lin[1].x, lin[2].x)),
                  glm::length(glm::vec3(lin[0].y, lin[1].y, lin[2].y)),
                  glm::length(glm::vec3(lin[0].z, lin[1].z, lin[2].z)));
    growBounds(c - ext);
    growBounds(c + ext);
    primBounds.push_back({c - ext, c + ext});
    out.primitives.push_back(p);
    return static_cast<std::uint32_t>(out.primitives.size() - 1);
}

std::uint32_t Builder::internalMaterial(glm::vec3 emission) {
    gpu::GpuMaterial m{};
    m.albedo = glm::vec4(0, 0, 0, 0);
    m.emission = glm::vec4(emission, 0);
    m.info = glm::uvec4(MAT_DIFFUSE, 0, 0, 0);
    out.materials.push_back(m);
    return static_cast<std::uint32_t>(out.materials.size() - 1);
}

bool Builder::run() {
    out = CompiledScene{};
    reusing = canReuse();
    out.boundsMin = glm::vec3(std::numeric_limits<float>::max());
    out.boundsMax = glm::vec3(-std::numeric_limits<float>::max());
    const std::string sceneDir = sceneFolder(scene);
    for (size_t i = 0; i < scene.materials.size(); ++i)
        if (!addMaterial(scene.materials[i], "materials[" + std::to_string(i) + "]", sceneDir)) return false;
    // Parts after all of them: a scene material's index is its place in the scene's list.
    for (size_t i = 0; i < scene.materials.size(); ++i) addSurfaceParts(static_cast<std::uint32_t>(i), scene.materials[i]);
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        const std::string where = "objects[" + std::to_string(i) + "]";
        if (o.shape == Shape::Mesh && o.material.empty()) {  // the file's own materials
            if (!addMeshInstance(o, static_cast<std::uint32_t>(i), o.transform.toMatrix(), kFileMaterials, nullptr, true,
                                 where))
                return false;
            continue;
        }
        auto it = std::find_if(scene.materials.begin(), scene.materials.end(),
                               [&](const Material& m) { return m.name == o.material; });
        if (it == scene.materials.end()) {
            *error = where + ".material: unknown material '" + o.material + "'";
            return false;
        }
        auto mat = static_cast<std::uint32_t>(it - scene.materials.begin());
        // The object's own emission (one-sided unless two_sided) replaces its material's
        // (two-sided) in a copy of the material that only this object uses.
        glm::vec3 emission = it->emission;
        bool twoSided = true;
        if (o.emits()) {
            emission = o.emission;
            twoSided = o.twoSided;
            gpu::GpuMaterial copy = out.materials[mat];
            copy.emission = glm::vec4(emission, copy.emission.w);  // w: the normal scale
            out.materials.push_back(copy);
            mat = static_cast<std::uint32_t>(out.materials.size() - 1);
        }
        if (o.shape != Shape::Mesh && it->alphaMode == AlphaMode::Mask)
            out.warnings.push_back(where + ": material '" + it->name + "' has alpha_mode 'mask', which only "
                                   "meshes honour: this " + std::string(enumName(o.shape)) + " is opaque");
        const bool emissive = glm::any(glm::greaterThan(emission, glm::vec3(0.0f)));
        const std::uint32_t primFlags = emissive && !twoSided ? PRIM_FLAG_ONE_SIDED_EMITTER : 0u;
        glm::mat4 m = o.transform.toMatrix();
        switch (o.shape) {
            case Shape::Mesh: {
                if (!addMeshInstance(o, static_cast<std::uint32_t>(i), m, mat, emissive ? &emission : nullptr,
                                     twoSided, where))
                    return false;
                break;
            }
            case Shape::Sphere: {
                std::uint32_t p = addSphere(m, mat, primFlags);
                if (emissive && !addSphereLight(p, m, emission, where, twoSided)) return false;
                break;
            }
            case Shape::Quad: {
                std::uint32_t p = addQuad(m, mat, primFlags);
                if (emissive && !addRectLight(p, emission, twoSided, where)) return false;
                break;
            }
            case Shape::Box: {
                // Six faces of [-1,1]^3, each the canonical quad turned to face outward.
                const glm::mat4 I(1.0f);
                const glm::vec3 X(1, 0, 0), Y(0, 1, 0);
                const glm::mat4 faces[6] = {
                    glm::translate(I, {0, 0, 1}),
                    glm::rotate(glm::translate(I, {0, 0, -1}), kPi, Y),
                    glm::rotate(glm::translate(I, {1, 0, 0}), kPi / 2, Y),
                    glm::rotate(glm::translate(I, {-1, 0, 0}), -kPi / 2, Y),
                    glm::rotate(glm::translate(I, {0, 1, 0}), -kPi / 2, X),
                    glm::rotate(glm::translate(I, {0, -1, 0}), kPi / 2, X),
                };
                for (const glm::mat4& f : faces) {
                    std::uint32_t p = addQuad(m * f, mat, primFlags);
                    if (emissive && !addRectLight(p, emission, twoSided, where)) return false;
                }
                break;
            }
        }
    }
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& L = scene.lights[i];
        const std::string where = "lights[" + std::to_string(i) + "]";
        switch (L.type) {
            case LightType::Rect: {
                std::uint32_t p = addQuad(L.transform.toMatrix(), internalMaterial(L.color),
                                          L.twoSided ? 0u : PRIM_FLAG_ONE_SIDED_EMITTER);
                if (!addRectLight(p, L.color, L.twoSided, where + ".transform")) return false;
                break;
            }
            case LightType::Sphere: {
                glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), L.position), glm::vec3(L.radius));
                std::uint32_t p = addSphere(m, internalMaterial(L.color));
                if (!addSphereLight(p, m, L.color, where + ".radius")) return false;
                break;
            }
            case LightType::Point:
            case LightType::Spot: {
                gpu::GpuLight l{};
                l.p0 = glm::vec4(L.position, 0);
                l.color = glm::vec4(L.color, 0);
                float power = 4.0f * kPi * luminance(L.color);
                if (L.type == LightType::Spot) {
                    float cosOuter = std::cos(glm::radians(L.outerAngle));
                    float cosInner = std::cos(glm::radians(L.innerAngle));
                    // smoothstep needs edge0 < edge1.
                    if (cosInner <= cosOuter) cosInner = cosOuter + 1e-6f;
                    const float outer = glm::radians(L.outerAngle), inner = glm::radians(L.innerAngle);
                    // Normalised in double: a direction as short as 1e-44 (a float denormal)
                    // has a length whose square underflows in float.
                    l.p1 = glm::vec4(glm::vec3(glm::normalize(glm::dvec3(L.direction))), cosOuter);
                    l.p2 = glm::vec4(outer, inner, 0, cosInner);
                    if (L.falloff == SpotFalloff::Smoothstep) {
                        // PBRT 4th ed. eq. 12.3 (the smoothstep falloff's approximate power).
                        power = 2.0f * kPi * luminance(L.color) * (1.0f - 0.5f * (cosInner + cosOuter));
                    } else {
                        // Linear in the angle: 2 pi I (integral of the falloff times sin theta),
                        // the ring by the midpoint rule.
                        double ring = 0.0;
                        constexpr int kSteps = 256;
                        for (int k = 0; k < kSteps; ++k) {
                            const double th = inner + (outer - inner) * (k + 0.5) / kSteps;
                            ring += (outer - th) / std::max(double(outer - inner), 1e-12) * std::sin(th) *
                                    (outer - inner) / kSteps;
                        }
                        power = static_cast<float>(2.0 * kPi * luminance(L.color) * (1.0 - std::cos(inner) + ring));
                    }
                }
                std::uint32_t flags = 0;
                if (L.type == LightType::Spot && L.falloff == SpotFalloff::LinearAngle) flags |= LIGHT_FLAG_LINEAR_ANGLE;
                l.info = glm::uvec4(L.type == LightType::Spot ? LIGHT_SPOT : LIGHT_POINT, flags, 0, 0);
                LightBounds bounds;
                bounds.boundsMin = bounds.boundsMax = L.position;
                bounds.intensity = luminance(L.color);
                if (L.type == LightType::Spot) {  // full intensity inside the inner cone, none beyond the outer
                    bounds.axis = glm::vec3(l.p1);
                    bounds.cosThetaO = l.p2.w;
                    bounds.cosThetaE = std::cos(std::max(std::acos(std::clamp(l.p1.w, -1.0f, 1.0f)) -
                                                             std::acos(std::clamp(l.p2.w, -1.0f, 1.0f)), 0.0f));
                }
                addLight(l, power, -1, bounds);
                growBounds(L.position);
                break;
            }
        }
    }
    if (!finishGeometry()) return false;
    if (out.primitives.empty() && out.lights.empty() && out.instances.empty())
        out.boundsMin = out.boundsMax = glm::vec3(0.0f);
    const Environment& env = scene.environment;
    if (env.type == EnvironmentType::Map) {
        if (env.file.empty()) {
            *error = "environment.file: a map environment needs a file";
            return false;
        }
        const std::filesystem::path file(resolveScenePath(scene, env.file));
        ImageData image;
        std::string why;
        if (!readImage) {
            *error = "environment.file: " + file.string() + ": this build cannot read images";
            return false;
        }
        if (!readImage(file.string(), &image, &why) || !buildEnvironmentMap(image, &out.envMap, &why)) {
            *error = "environment.file: " + why;
            return false;
        }
        // The same bound as the scene reader's on emitted radiance (renderer/scene_io.cpp,
        // kMaxRadiance: the film's float sums of squares stay finite).
        float brightest = 0.0f;
        for (size_t k = 0; k < image.pixels.size(); ++k)
            if (image.channels < 4 || k % 4 != 3) brightest = std::max(brightest, image.pixels[k]);
        if (double(brightest) * env.intensity > 1e12) {
            *error = "environment.file: " + file.string() + ": the brightest texel (" + formatShort(brightest) +
                     ") times the intensity exceeds 1e12, the most a channel may emit";
            return false;
        }
    }
    if (!scene.camera.apertureImage.empty() && !readApertureImage(scene, readImage, &out.aperture, error)) return false;
    if (env.type != EnvironmentType::None) {
        glm::vec3 average = env.type == EnvironmentType::Constant ? env.radiance
                            : env.type == EnvironmentType::Map   ? out.envMap.average
                                // mean of the sky over the sphere: horizon below, and the
                                // mean of sqrt(y) over the upper half (y uniform) is 2/3.
                                : env.horizon + (env.zenith - env.horizon) / 3.0f;
        average *= env.intensity;
        // In double: the bounds of an object at 1e19 give a radius whose square, times pi^2,
        // overflows a float (the pmfs became inf / inf = NaN).
        double radius = 0.5 * glm::length(glm::dvec3(out.boundsMax) - glm::dvec3(out.boundsMin));
        radius = std::max(radius, 1e-3);
        gpu::GpuLight l{};
        l.info = glm::uvec4(LIGHT_ENV, 0, 0, 0);
        out.envLightIndex = static_cast<int>(out.lights.size());
        // Power an infinite light delivers into the scene's bounding sphere: pi * pi r^2 * L
        // (power selection). The light tree weighs it by the irradiance it gives a surface,
        // pi * L, in the same unit as a tree node's importance (lights/light_select.glsl).
        addLight(l, saturatedPower(kPi * kPi * radius * radius * luminance(average)), -1, LightBounds{});
        out.envImportance = kPi * luminance(average);
    }
    // The light tree over every other light.
    std::vector<std::uint32_t> members;
    for (size_t i = 0; i < out.lights.size(); ++i)
        if (static_cast<int>(i) != out.envLightIndex) members.push_back(static_cast<std::uint32_t>(i));
    out.lightTree = buildLightTree(out.lightBounds, members);
    for (size_t i = 0; i < out.lights.size(); ++i) out.lights[i].tree.x = out.lightTree.trails[i];
    // Selection probabilities: by power (default) or uniform; uniform when nothing emits.
    double total = 0.0;
    for (float p : out.lightPower) total += p;
    bool uniform = scene.render.lightSelection == LightSelection::Uniform || !(total > 0.0);
    double acc = 0.0;
    const size_t n = out.lights.size();
    for (size_t i = 0; i < n; ++i) {
        double pmf = uniform ? 1.0 / double(n) : out.lightPower[i] / total;
        out.lights[i].color.w = static_cast<float>(pmf);
        acc += pmf;
        out.lightCdf.push_back(static_cast<float>(acc));
    }
    if (!out.lightCdf.empty()) out.lightCdf.back() = 1.0f;
    return true;
}

}  // namespace scene_compile

using scene_compile::Builder;


bool readApertureImage(const Scene& scene, const ImageReader& readImage, ApertureImage* out, std::string* error) {
    const std::string file = resolveScenePath(scene, scene.camera.apertureImage);
    ImageData image;
    std::string why;
    if (!readImage) {
        *error = "camera.aperture_image: " + file + ": this build cannot read images";
        return false;
    }
    if (!readImage(file, &image, &why)) {
        *error = "camera.aperture_image: " + why;
        return false;
    }
    if (!buildApertureImage(image, out, &why)) {
        *error = "camera.aperture_image: " + file + ": " + why;
        return false;
    }
    return true;
}

bool buildApertureImage(const ImageData& image, ApertureImage* out, std::string* error) {
    if (image.width <= 0 || image.height <= 0 || image.channels <= 0 ||
        image.pixels.size() < std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels)) {
        *error = "the image has no pixels";
        return false;
    }
    // Box-average down by an integer factor until both sides fit.
    const int factor = std::max((image.width + kMaxApertureSide - 1) / kMaxApertureSide,
                                (image.height + kMaxApertureSide - 1) / kMaxApertureSide);
    ApertureImage a;
    a.width = (image.width + factor - 1) / factor;
    a.height = (image.height + factor - 1) / factor;
    a.mask.assign(std::size_t(a.width) * std::size_t(a.height), 0.0f);
    const int colours = std::min(image.channels, 3);
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            double sum = 0.0;
            int count = 0;
            for (int sy = y * factor; sy < std::min((y + 1) * factor, image.height); ++sy)
                for (int sx = x * factor; sx < std::min((x + 1) * factor, image.width); ++sx) {
                    const float* p = &image.pixels[(std::size_t(sy) * std::size_t(image.width) + std::size_t(sx)) *
                                                   std::size_t(image.channels)];
                    double v = 0.0;
                    for (int c = 0; c < colours; ++c) v += std::isfinite(p[c]) ? p[c] : 0.0;
                    sum += std::clamp(v / colours, 0.0, 1.0);
                    ++count;
                }
            a.mask[std::size_t(y) * std::size_t(a.width) + std::size_t(x)] = float(sum / count);
        }
    std::vector<double> rows(std::size_t(a.height), 0.0);
    double total = 0.0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) rows[std::size_t(y)] += a.mask[std::size_t(y) * std::size_t(a.width) + std::size_t(x)];
        total += rows[std::size_t(y)];
    }
    if (!(total > 0.0)) {
        *error = "the image is black everywhere: no light would pass the aperture";
        return false;
    }
    a.marginalCdf.push_back(0.0f);
    double acc = 0.0;
    for (int y = 0; y < a.height; ++y) {
        acc += rows[std::size_t(y)];
        a.marginalCdf.push_back(float(acc / total));
        double rowAcc = 0.0;
        a.conditionalCdf.push_back(0.0f);
        for (int x = 0; x < a.width; ++x) {
            rowAcc += a.mask[std::size_t(y) * std::size_t(a.width) + std::size_t(x)];
            // A row of zero weight gets a uniform CDF (never chosen).
            a.conditionalCdf.push_back(rows[std::size_t(y)] > 0.0 ? float(rowAcc / rows[std::size_t(y)])
                                                                  : float(x + 1) / float(a.width));
        }
        a.conditionalCdf.back() = 1.0f;
    }
    a.marginalCdf.back() = 1.0f;
    *out = std::move(a);
    return true;
}

bool compileScene(const Scene& scene, const ImageReader& readImage, CompiledScene* out, std::string* error,
                  MeshCache* meshCache, CompiledScene* reuse) {
    Builder b(scene, readImage, *out, error, meshCache, reuse == out ? nullptr : reuse);
    if (b.run()) return true;
    b.restoreReuse();
    return false;
}

}  // namespace caustic
