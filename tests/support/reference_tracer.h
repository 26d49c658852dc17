// An independent CPU path tracer, for checking the GPU integrator's converged images.
//
// It estimates one number per channel: the mean radiance over the whole image (box filter, a
// uniformly random point of the image per path), with its standard error. It shares no code with
// the GLSL on purpose, so that a bug there cannot hide here:
//   - double precision throughout (the scene's float data is widened once);
//   - its own intersection code, derived afresh: quads by solving the 2x2 Gram system of the two
//     edges, spheres (any affine image of the unit sphere) by the textbook quadratic in object space;
//   - its own random numbers (xoshiro256**, seeded with splitmix64; Blackman and Vigna 2018);
//   - its own sampling: the cosine-weighted direction is n + (a uniform point on the unit sphere),
//     normalised, which is exactly cosine-distributed about n (the unit sphere centred at n
//     touches the tangent plane at the origin; its uniform area seen from there has density
//     cos(theta) / pi), so no tangent frame is needed;
//   - BSDF sampling only, with emission counted at every vertex: no light sampling, no MIS, no
//     light-selection probabilities. For a Lambertian surface the sample weight f cos / pdf is
//     the albedo, so the path throughput is just the product of albedos.
// It is slow to converge on small lights, which is why it checks a mean over the whole image and
// not pixels.
//
// Semantics it must share with the GPU (they define the integral, not the estimator):
//   - the camera: its frame comes from renderer/camera.h's cameraFrame (the one module the
//     renderer and the editor use too; the shader's rays are tested against it on the GPU), as a
//     pinhole, row 0 at the top;
//   - max depth = the maximum number of scattering events on a path: emission is collected at
//     the first maxDepth + 1 surface hits (0: only emitters seen directly);
//   - every material emits from both faces, except primitives flagged
//     PRIM_FLAG_ONE_SIDED_EMITTER (rect lights, objects with their own emission), which emit
//     from their front only (a quad's front normal is cross(edge u, edge v); a sphere's is
//     outward); an emitter also scatters by its material (the Cornell box's light is white);
//   - every surface is two-sided Lambertian (MAT_DIFFUSE is the only material so far);
//   - rays that leave the scene see the environment (none / constant / sky; other kinds are
//     refused); meshes are refused too.
// Russian roulette (unbiased) shortens long paths. Delta lights (point, spot) cannot be hit by a
// BSDF-sampled ray, so scenes with them are refused.
//
// Deterministic: the paths are cut into a fixed number of chunks, each with its own random
// stream, and the chunk sums are added in order, so the result does not depend on the threads.
#pragma once

#include "renderer/camera.h"
#include "renderer/gpu_scene.h"
#include "renderer/scene.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace caustic::test::reference {

struct TracerSettings {
    std::uint64_t paths = 1u << 20;  // one camera path each (its estimate is one sample)
    std::uint64_t seed = 1;
    unsigned threads = 0;            // 0: std::thread::hardware_concurrency()
};

struct MeanEstimate {
    glm::dvec3 mean{0.0};
    glm::dvec3 standardError{0.0};  // sqrt(unbiased sample variance / paths)
    std::uint64_t paths = 0;
    double seconds = 0.0;
    std::string error;              // non-empty: the scene is not supported, nothing was traced
};

namespace detail {

constexpr double kPi = 3.14159265358979323846;

inline std::uint64_t splitmix64(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// xoshiro256** 1.0 (https://prng.di.unimi.it/xoshiro256starstar.c).
class Rng {
public:
    explicit Rng(std::uint64_t seed) {
        for (auto& w : m_s) w = splitmix64(seed);
    }
    std::uint64_t next() {
        const std::uint64_t result = rotl(m_s[1] * 5, 7) * 9;
        const std::uint64_t t = m_s[1] << 17;
        m_s[2] ^= m_s[0];
        m_s[3] ^= m_s[1];
        m_s[1] ^= m_s[2];
        m_s[0] ^= m_s[3];
        m_s[2] ^= t;
        m_s[3] = rotl(m_s[3], 45);
        return result;
    }
    // Uniform in [0, 1) with 53 random bits.
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }

private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    std::uint64_t m_s[4];
};

struct Quad {
    glm::dvec3 corner, eu, ev;
    glm::dvec3 normal;       // unit, cross(eu, ev) direction: the front
    double gInv[3];          // inverse Gram matrix of (eu, ev): [a b; b c] stored as a, b, c
};

struct Ellipsoid {
    glm::dmat3 lin;          // world-to-object linear part (row-major use: objectP = lin * p + off)
    glm::dvec3 off;
};

struct Prim {
    bool sphere = false;
    Quad quad{};
    Ellipsoid ell{};
    glm::dvec3 albedo{0.0};
    glm::dvec3 emission{0.0};
    bool emits = false;
    bool oneSided = false;
};

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    int prim = -1;
};

class Tracer {
public:
    Tracer(const Scene& scene, const CompiledScene& compiled, std::string* error) {
        for (const gpu::GpuPrimitive& p : compiled.primitives) {
            Prim q;
            const gpu::GpuMaterial& m = compiled.materials.at(p.info.y);
            if (m.info.x != MAT_DIFFUSE) {
                *error = "reference tracer: only diffuse materials are supported";
                return;
            }
            q.albedo = glm::dvec3(glm::vec3(m.albedo));
            q.emission = glm::dvec3(glm::vec3(m.emission));
            q.emits = std::max({q.emission.x, q.emission.y, q.emission.z}) > 0.0;
            q.oneSided = (p.info.w & PRIM_FLAG_ONE_SIDED_EMITTER) != 0u;
            if (p.info.x == PRIM_SPHERE) {
                q.sphere = true;
                // Rows a, b, c of the affine world-to-object map.
                const glm::vec4 rows[3] = {p.a, p.b, p.c};
                for (int r = 0; r < 3; ++r) {
                    for (int c = 0; c < 3; ++c) q.ell.lin[c][r] = double(rows[r][c]);  // glm: [column][row]
                    q.ell.off[r] = double(rows[r].w);
                }
            } else {
                q.quad.corner = glm::dvec3(glm::vec3(p.a));
                q.quad.eu = glm::dvec3(glm::vec3(p.b));
                q.quad.ev = glm::dvec3(glm::vec3(p.c));
                q.quad.normal = glm::normalize(glm::cross(q.quad.eu, q.quad.ev));
                const double a = glm::dot(q.quad.eu, q.quad.eu), b = glm::dot(q.quad.eu, q.quad.ev),
                             c = glm::dot(q.quad.ev, q.quad.ev);
                const double det = a * c - b * b;
                if (!(det > 0.0)) continue;  // degenerate: has no area, can never be hit
                q.quad.gInv[0] = c / det;
                q.quad.gInv[1] = -b / det;
                q.quad.gInv[2] = a / det;
            }
            m_prims.push_back(q);
        }
        if (!compiled.instances.empty()) {  // it would miss them silently
            *error = "reference tracer: meshes are not supported";
            return;
        }
        for (const Light& l : scene.lights) {
            if (l.type == LightType::Point || l.type == LightType::Spot) {
                *error = "reference tracer: delta lights cannot be reached by BSDF sampling";
                return;
            }
        }
        m_env = scene.environment;
        if (m_env.type != EnvironmentType::None && m_env.type != EnvironmentType::Constant &&
            m_env.type != EnvironmentType::Sky) {
            *error = "reference tracer: only no, constant and sky environments are supported";
            return;
        }
        // The camera's frame (renderer/camera.h, the one the renderer and the editor use).
        const CameraFrame cam = cameraFrame(scene.camera, scene.render.width, scene.render.height);
        m_camPos = cam.position;
        m_forward = cam.forward;
        m_right = cam.right * cam.tanX;
        m_up = cam.up * cam.tanY;
        m_maxDepth = scene.render.maxDepth;
    }

    // One path through a uniformly random point of the image.
    glm::dvec3 samplePath(Rng& rng) const {
        const double sx = 2.0 * rng.uniform() - 1.0, sy = 2.0 * rng.uniform() - 1.0;
        glm::dvec3 o = m_camPos;
        glm::dvec3 d = glm::normalize(m_forward + sx * m_right + sy * m_up);
        glm::dvec3 beta(1.0), L(0.0);
        int from = -1;
        for (int bounce = 0;; ++bounce) {
            Hit hit = closest(o, d, from);
            if (hit.prim < 0) {
                L += beta * environment(d);
                break;
            }
            const Prim& p = m_prims[hit.prim];
            const glm::dvec3 x = o + hit.t * d;
            const glm::dvec3 n = p.sphere ? sphereNormal(p.ell, x) : p.quad.normal;
            const bool front = glm::dot(n, d) < 0.0;
            if (p.emits && (front || !p.oneSided)) L += beta * p.emission;
            if (bounce >= m_maxDepth) break;
            beta *= p.albedo;  // Lambertian, cosine sampled: f cos / pdf = albedo
            const double q = std::min(1.0, std::max({beta.x, beta.y, beta.z}));
            if (q <= 0.0) break;
            if (bounce >= 4) {  // Russian roulette, unbiased for any q in (0, 1]
                if (rng.uniform() >= q) break;
                beta /= q;
            }
            const glm::dvec3 ns = front ? n : -n;  // the side the ray came from
            d = cosineDirection(ns, rng);
            o = x;
            from = hit.prim;
        }
        return L;
    }

private:
    glm::dvec3 environment(const glm::dvec3& d) const {
        switch (m_env.type) {
            case EnvironmentType::None: return glm::dvec3(0.0);
            case EnvironmentType::Constant: return glm::dvec3(m_env.radiance) * double(m_env.intensity);
            case EnvironmentType::Sky: {
                // docs/scene-format.md: horizon at and below the horizon, zenith straight up,
                // blended with sqrt(max(y, 0)).
                const double s = std::sqrt(std::clamp(d.y, 0.0, 1.0));
                return (glm::dvec3(m_env.horizon) * (1.0 - s) + glm::dvec3(m_env.zenith) * s) *
                       double(m_env.intensity);
            }
            default: return glm::dvec3(0.0);  // refused in the constructor
        }
    }

    static glm::dvec3 cosineDirection(const glm::dvec3& n, Rng& rng) {
        for (;;) {
            const double z = 1.0 - 2.0 * rng.uniform();
            const double phi = 2.0 * kPi * rng.uniform();
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const glm::dvec3 v = n + glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
            const double len = glm::length(v);
            if (len > 1e-9) return v / len;  // v = 0 only when the sphere point is exactly -n
        }
    }

    static glm::dvec3 sphereNormal(const Ellipsoid& e, const glm::dvec3& x) {
        // The object-space normal is the object point; normals map by the transpose of the
        // world-to-object linear part.
        const glm::dvec3 po = e.lin * x + e.off;
        return glm::normalize(glm::transpose(e.lin) * po);
    }

    // Ray from the surface of primitive `from` (or the camera, -1): a quad cannot be hit again by
    // a ray leaving it (it is flat), a sphere only at a distance well above rounding.
    Hit closest(const glm::dvec3& o, const glm::dvec3& d, int from) const {
        Hit best;
        for (int i = 0; i < int(m_prims.size()); ++i) {
            const Prim& p = m_prims[i];
            double t;
            if (p.sphere) {
                const double tMin = i == from ? 1e-9 * std::max(1.0, glm::length(o)) : 0.0;
                if (!hitEllipsoid(p.ell, o, d, tMin, &t)) continue;
            } else {
                if (i == from || !hitQuad(p.quad, o, d, &t)) continue;
            }
            if (t < best.t) {
                best.t = t;
                best.prim = i;
            }
        }
        return best;
    }

    static bool hitQuad(const Quad& q, const glm::dvec3& o, const glm::dvec3& d, double* t) {
        const double denom = glm::dot(q.normal, d);
        if (denom == 0.0) return false;
        const double tt = glm::dot(q.normal, q.corner - o) / denom;
        if (!(tt > 0.0)) return false;
        // x - corner = s eu + r ev: least squares (exact, x is in the plane) via the Gram matrix.
        const glm::dvec3 rel = o + tt * d - q.corner;
        const double pu = glm::dot(rel, q.eu), pv = glm::dot(rel, q.ev);
        const double s = q.gInv[0] * pu + q.gInv[1] * pv;
        const double r = q.gInv[1] * pu + q.gInv[2] * pv;
        if (s < 0.0 || s > 1.0 || r < 0.0 || r > 1.0) return false;
        *t = tt;
        return true;
    }

    static bool hitEllipsoid(const Ellipsoid& e, const glm::dvec3& o, const glm::dvec3& d, double tMin, double* t) {
        const glm::dvec3 oo = e.lin * o + e.off, dd = e.lin * d;
        // |oo + t dd|^2 = 1
        const double a = glm::dot(dd, dd), b = glm::dot(oo, dd), c = glm::dot(oo, oo) - 1.0;
        const double disc = b * b - a * c;
        if (disc < 0.0) return false;
        const double sq = std::sqrt(disc);
        const double t0 = (-b - sq) / a, t1 = (-b + sq) / a;
        if (t0 > tMin) { *t = t0; return true; }
        if (t1 > tMin) { *t = t1; return true; }
        return false;
    }

    std::vector<Prim> m_prims;
    Environment m_env;
    glm::dvec3 m_camPos{0.0}, m_forward{0.0}, m_right{0.0}, m_up{0.0};
    int m_maxDepth = 0;
};

}  // namespace detail

// The mean radiance over the image of `scene` (camera, resolution, max depth, environment from
// `scene`; geometry, materials and emitter flags from `compiled`, which must be compileScene's
// output for it).
inline MeanEstimate estimateImageMean(const Scene& scene, const CompiledScene& compiled,
                                      const TracerSettings& settings) {
    MeanEstimate out;
    detail::Tracer tracer(scene, compiled, &out.error);
    if (!out.error.empty() || settings.paths < 2) {
        if (out.error.empty()) out.error = "reference tracer: needs at least two paths";
        return out;
    }
    const auto t0 = std::chrono::steady_clock::now();
    constexpr std::uint64_t kChunks = 256;
    struct Sums { glm::dvec3 sum{0.0}, sumSq{0.0}; };
    std::vector<Sums> chunks(kChunks);
    std::atomic<std::uint64_t> next{0};
    auto work = [&] {
        for (std::uint64_t c; (c = next.fetch_add(1)) < kChunks;) {
            std::uint64_t seedState = settings.seed * 0x632be59bd9b4e019ull + c;
            detail::Rng rng(detail::splitmix64(seedState));
            const std::uint64_t begin = settings.paths * c / kChunks, end = settings.paths * (c + 1) / kChunks;
            Sums s;
            for (std::uint64_t i = begin; i < end; ++i) {
                const glm::dvec3 L = tracer.samplePath(rng);
                s.sum += L;
                s.sumSq += L * L;
            }
            chunks[c] = s;
        }
    };
    unsigned threads = settings.threads ? settings.threads : std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned i = 1; i < threads; ++i) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    Sums total;
    for (const Sums& s : chunks) {
        total.sum += s.sum;
        total.sumSq += s.sumSq;
    }
    const double n = double(settings.paths);
    out.paths = settings.paths;
    out.mean = total.sum / n;
    const glm::dvec3 variance = glm::max((total.sumSq - total.sum * out.mean) / (n - 1.0), glm::dvec3(0.0));
    out.standardError = glm::sqrt(variance / n);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace caustic::test::reference
