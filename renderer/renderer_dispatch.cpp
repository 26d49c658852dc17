// Rendering: binding the scene, dispatching the integrator (batch renders and the editor's
// time-budgeted frames), and reading the counters and the film back.
#include "renderer/renderer.h"
#include "renderer/renderer_internal.h"

#include "renderer/bsdf_tables.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <string_view>

namespace caustic {
namespace {

constexpr std::uint32_t kMaxSamplesPerDispatch = 64;

// The GL format of a scene texel view from its GLSL image format's name (TEXUNIT_*_FORMAT in
// shaders/shared/layout.h). Evaluated at compile time (TEXEL_VIEW in bindScene): a name it does
// not know stops the build.
consteval GLenum texelViewFormat(std::string_view glslFormat) {
    if (glslFormat == "rgba32ui") return GL_RGBA32UI;
    if (glslFormat == "r32ui") return GL_R32UI;
    throw "texelViewFormat: a TEXUNIT_*_FORMAT that is neither rgba32ui nor r32ui";
}

void waitFence(GLsync fence) {
    while (glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 100'000'000) == GL_TIMEOUT_EXPIRED) {}
    glDeleteSync(fence);
}

}  // namespace

void Renderer::setStrategy(std::uint32_t strategy) {
    m_strategy = strategy;
    // The program is built by the next setScene or dispatch: caustic sets the strategy before the
    // scene, and building it here made a program for the empty scene (2 s on llvmpipe) never used.
    resetAccumulation();
}

void Renderer::resetAccumulation() {
    const float zero[4] = {0, 0, 0, 0};
    if (m_accum) {
        glClearTexImage(m_accum, 0, GL_RGBA, GL_FLOAT, zero);
        glClearTexImage(m_accumSq, 0, GL_RGBA, GL_FLOAT, zero);
        glClearTexImage(m_albedo, 0, GL_RGBA, GL_FLOAT, zero);
        glClearTexImage(m_normal, 0, GL_RGBA, GL_FLOAT, zero);
    }
    const std::uint32_t counters[COUNTER_WORDS] = {};
    glNamedBufferSubData(m_counters, 0, sizeof counters, counters);
    m_samplesDone = 0;
    m_bandTile = 0;
}

void Renderer::bindScene(std::uint32_t firstSample, std::uint32_t samples) { bindScene(firstSample, samples, 0, ~0u); }

std::uint32_t Renderer::tileCount() const {
    return ((static_cast<std::uint32_t>(m_width) + 7) / 8) * ((static_cast<std::uint32_t>(m_height) + 7) / 8);
}

void Renderer::bindScene(std::uint32_t firstSample, std::uint32_t samples, std::uint32_t tile0, std::uint32_t tile1) {
    gpu::GpuFrame frame = makeFrame(m_scene, m_compiled, m_strategy);
    frame.image.z = m_sampleBase + firstSample;
    frame.dispatch.x = samples;
    frame.options.y = static_cast<std::uint32_t>(m_region.x0);   // the crop's origin (path.comp)
    frame.options.z = static_cast<std::uint32_t>(m_region.y0);
    frame.dispatch.z = tile0;
    frame.dispatch.w = std::min(tile1, tileCount());
    // A fresh buffer store per dispatch (orphaning) so an in-flight dispatch keeps its constants.
    glNamedBufferData(m_frameUbo, sizeof frame, &frame, GL_STREAM_DRAW);
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_FRAME_UBO, m_frameUbo);
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_LENS_UBO, m_lensUbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PRIMITIVES, m_primitives);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PRIMITIVE_HITS, m_primitiveHits);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_MATERIALS, m_materials);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_LIGHTS, m_lights);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_LIGHT_TREE, m_lightTree);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TABLES, m_tables);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_COUNTERS, m_counters);
    const unsigned geometryBindings[kGeometryBuffers] = {BINDING_BVH_NODES, BINDING_TLAS_REFS, BINDING_INSTANCES,
                                                         BINDING_TRIANGLES, BINDING_VERTICES};
    for (int i = 0; i < kGeometryBuffers; ++i)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, geometryBindings[i], m_geometry[i]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEXELS, m_texels);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEXTURES, m_textures);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_BSDF_TABLES, m_bsdfTables);
    glBindTextureUnit(TEXUNIT_ENV_MAP, m_envTexture);
    // The buffer textures over the same buffers (read instead of them with CAUSTIC_FETCH_TEXELS,
    // shaders/scene/buffers.glsl), attached again each time: an upload may have replaced a
    // buffer's data store, and with it its size.
    // Each view's format is its unit's TEXUNIT_*_FORMAT (shaders/shared/layout.h), the GLSL image
    // format's name that the shaders' declarations use too, spelled here as the GL enum.
#define TEXEL_VIEW(unit, buffer) {unit, buffer, texelViewFormat(TEXEL_VIEW_FORMAT_NAME(unit##_FORMAT))}
#define TEXEL_VIEW_FORMAT_NAME(format) TEXEL_VIEW_STRING(format)
#define TEXEL_VIEW_STRING(format) #format
    const struct { unsigned unit, buffer; GLenum format; } views[kTexelViews] = {
        TEXEL_VIEW(TEXUNIT_PRIMITIVES, m_primitives),        TEXEL_VIEW(TEXUNIT_BVH_NODES, m_geometry[0]),
        TEXEL_VIEW(TEXUNIT_TRIANGLES, m_geometry[3]),        TEXEL_VIEW(TEXUNIT_TLAS_REFS, m_geometry[1]),
        TEXEL_VIEW(TEXUNIT_INSTANCES, m_geometry[2]),        TEXEL_VIEW(TEXUNIT_MATERIALS, m_materials),
        TEXEL_VIEW(TEXUNIT_PRIMITIVE_HITS, m_primitiveHits), TEXEL_VIEW(TEXUNIT_WIDE_NODES, m_wideNodes),
        TEXEL_VIEW(TEXUNIT_VERTICES, m_geometry[4]),         TEXEL_VIEW(TEXUNIT_TABLES, m_tables),
        TEXEL_VIEW(TEXUNIT_LIGHTS, m_lights),                TEXEL_VIEW(TEXUNIT_LIGHT_TREE, m_lightTree),
        TEXEL_VIEW(TEXUNIT_BSDF_TABLES, m_bsdfTables)};
#undef TEXEL_VIEW_STRING
#undef TEXEL_VIEW_FORMAT_NAME
#undef TEXEL_VIEW
    for (int i = 0; i < kTexelViews; ++i) {
        glTextureBuffer(m_texelViews[i], views[i].format, views[i].buffer);
        glBindTextureUnit(views[i].unit, m_texelViews[i]);
        // The same views as images, for a program that reads them so (CAUSTIC_IMAGE_LOADS), where
        // the context has the image units (GL guarantees 8).
        if (m_imageLoads)
            glBindImageTexture(IMAGE_UNIT_TEXELS + views[i].unit, m_texelViews[i], 0, GL_FALSE, 0, GL_READ_ONLY,
                               views[i].format);
    }
}

bool Renderer::programReady() {
    std::string error;
    if (!selectProgram(&error)) {
        if (m_waitingForBuild) {   // built in the background: nothing renders yet
            m_programError.clear();
            return false;
        }
        // setScene and update report this (unless builds are deferred); nothing renders, and no
        // sample is counted as rendered.
        if (error != m_programError) std::fprintf(stderr, "caustic: no integrator to render with: %s\n", error.c_str());
        m_programError = error;
        return false;
    }
    m_programError.clear();
    return true;
}

void Renderer::dispatch(std::uint32_t firstSample, std::uint32_t samples, std::uint32_t tile0, std::uint32_t tile1) {
    tile1 = std::min(tile1, tileCount());
    if (tile0 >= tile1) return;
    if (!programReady()) return;
    bindScene(firstSample, samples, tile0, tile1);
    glUseProgram(m_program);
    glBindImageTexture(BINDING_ACCUM_IMAGE, m_accum, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(BINDING_ACCUM_SQ_IMAGE, m_accumSq, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(BINDING_ALBEDO_IMAGE, m_albedo, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(BINDING_NORMAL_IMAGE, m_normal, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    // One work group per 8x8 tile, DISPATCH_STRIDES bands of them interleaved (integrator/path.comp);
    // a grid of at most 65535 groups a side (the least GL guarantees), the kernel skipping the
    // groups beyond the tiles.
    const std::uint32_t tiles = tile1 - tile0;
    const std::uint32_t groups = DISPATCH_STRIDES * ((tiles + DISPATCH_STRIDES - 1) / DISPATCH_STRIDES);
    const std::uint32_t gx = std::min<std::uint32_t>(groups, 65535u);
    glDispatchCompute(gx, (groups + gx - 1) / gx, 1);
    // The next dispatch reads what this one wrote.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void Renderer::render(int count, const std::function<void(int)>& progress) {
    if (count > 0 && !programReady()) return;
    using Clock = std::chrono::steady_clock;
    struct InFlight { GLsync fence; std::uint32_t samples; Clock::time_point issued; };
    std::deque<InFlight> inFlight;
    if (count > 0 && m_bandTile > 0) {  // first the rest of a sample that renderFor started
        finishBand();
        --count;
    }
    int issued = 0;
    const int firstSample = m_samplesDone;  // m_samplesDone counts retired samples only
    auto retireOldest = [&] {
        InFlight f = inFlight.front();
        inFlight.pop_front();
        waitFence(f.fence);
        // With two in flight the wait measures roughly one dispatch; smooth the estimate.
        double seconds = std::chrono::duration<double>(Clock::now() - f.issued).count() / double(f.samples);
        if (!inFlight.empty()) seconds *= 0.5;
        m_secondsPerSample = m_secondsPerSample == 0.0 ? seconds : 0.7 * m_secondsPerSample + 0.3 * seconds;
        m_samplesDone += static_cast<int>(f.samples);
        if (progress) progress(m_samplesDone);
    };
    const double target = m_config.dispatchSeconds;
    while (issued < count) {
        std::uint32_t n = 1;
        if (m_secondsPerSample > 0.0)
            n = static_cast<std::uint32_t>(std::clamp(target / m_secondsPerSample, 1.0, double(kMaxSamplesPerDispatch)));
        n = std::min<std::uint32_t>(n, static_cast<std::uint32_t>(count - issued));
        dispatch(static_cast<std::uint32_t>(firstSample + issued), n);
        inFlight.push_back({glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0), n, Clock::now()});
        issued += static_cast<int>(n);
        if (inFlight.size() >= 2) retireOldest();
    }
    while (!inFlight.empty()) retireOldest();
}

long long Renderer::tilePixels(std::uint32_t tile0, std::uint32_t tile1) const {
    // Tiles on the right and bottom edges may be partly outside the image.
    const std::uint32_t tilesX = (static_cast<std::uint32_t>(m_width) + 7) / 8;
    long long pixels = 0;
    for (std::uint32_t t = tile0; t < tile1; ++t) {
        const int x = static_cast<int>(t % tilesX) * 8, y = static_cast<int>(t / tilesX) * 8;
        pixels += static_cast<long long>(std::min(8, m_width - x)) * std::min(8, m_height - y);
    }
    return pixels;
}

double Renderer::finishBand() {
    const auto t0 = std::chrono::steady_clock::now();
    dispatch(static_cast<std::uint32_t>(m_samplesDone), 1, m_bandTile, ~0u);
    waitFence(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
    ++m_samplesDone;
    m_bandTile = 0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Renderer::Progress Renderer::renderFor(double budgetSeconds, int maxSamples) {
    using Clock = std::chrono::steady_clock;
    Progress p;
    if (maxSamples <= 0 || m_width <= 0 || m_height <= 0 || !programReady()) return p;
    const auto start = Clock::now();
    const long long pixels = static_cast<long long>(m_width) * m_height;
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    auto learn = [&](long long pixelSamples, double seconds) {
        if (pixelSamples <= 0 || !(seconds > 0.0)) return;
        const double v = seconds / double(pixelSamples);
        // Quick to follow a heavier scene (an edit), smooth otherwise.
        const double a = v > m_secondsPerPixelSample ? 0.6 : 0.3;
        m_secondsPerPixelSample = m_secondsPerPixelSample == 0.0 ? v : (1.0 - a) * m_secondsPerPixelSample + a * v;
    };
    // Whole samples while one of the whole image fits what is left of the budget. Unmeasured (a
    // new scene, a first call), the first band measures.
    while (m_bandTile == 0 && m_secondsPerPixelSample > 0.0 && p.samplesCompleted < maxSamples) {
        const double left = budgetSeconds - elapsed();
        const double perSample = m_secondsPerPixelSample * double(pixels);
        if (perSample > left) break;
        const int n = std::clamp(static_cast<int>(left / perSample), 1, maxSamples - p.samplesCompleted);
        const auto t0 = Clock::now();
        render(n);
        learn(pixels * n, std::chrono::duration<double>(Clock::now() - t0).count());
        p.samplesCompleted += n;
        p.pixelSamples += pixels * n;
    }
    // Else runs of 8x8 tiles (in rows of tiles) of the next sample; at least one tile per call,
    // so progress never stops (a tile of 64 pixels is the smallest unit of work: on llvmpipe a
    // row of tiles across a 512-pixel image took 20 ms, more than a frame's budget). Not after
    // whole samples: the call returns a little early instead, because every run that waits for its
    // dispatch to finish with nothing queued behind it costs throughput (docs/performance.md,
    // "An idle editor against batch mode").
    const std::uint32_t tiles = tileCount();
    while (p.samplesCompleted < maxSamples && !(p.samplesCompleted > 0 && m_bandTile == 0)) {
        const double left = budgetSeconds - elapsed();
        if (left <= 0.0 && p.pixelSamples > 0) break;
        // Tiles differ in cost (a wall, the sky) and the estimate lags: aim a little short.
        std::uint32_t n = 1;
        if (m_secondsPerPixelSample > 0.0)
            n = static_cast<std::uint32_t>(std::clamp(0.8 * left / (m_secondsPerPixelSample * 64.0), 1.0, double(tiles)));
        const std::uint32_t tile1 = std::min(tiles, m_bandTile + n);
        const auto t0 = Clock::now();
        dispatch(static_cast<std::uint32_t>(m_samplesDone), 1, m_bandTile, tile1);
        waitFence(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
        learn(64LL * (tile1 - m_bandTile), std::chrono::duration<double>(Clock::now() - t0).count());
        p.pixelSamples += tilePixels(m_bandTile, tile1);
        if (tile1 >= tiles) {
            m_bandTile = 0;
            ++m_samplesDone;
            ++p.samplesCompleted;
        } else {
            m_bandTile = tile1;
        }
    }
    p.seconds = elapsed();
    return p;
}

std::array<std::uint32_t, COUNTER_WORDS> Renderer::readCounters() const {
    std::array<std::uint32_t, COUNTER_WORDS> counters{};
    glGetNamedBufferSubData(m_counters, 0, sizeof counters, counters.data());
    return counters;
}

namespace {
// The 64-bit count in counter words (lo, lo + 1) (integrator/film.glsl, addCount64).
std::uint64_t count64(const std::array<std::uint32_t, COUNTER_WORDS>& counters, int lo) {
    return (std::uint64_t(counters[lo + 1]) << 32) | counters[lo];
}
}  // namespace

std::uint64_t Renderer::droppedSamples() const { return readCounters()[COUNTER_DROPPED]; }

std::uint64_t Renderer::raysTraced() const { return count64(readCounters(), COUNTER_RAYS_LO); }

WalkStats Renderer::walkStats() const {
    const auto counters = readCounters();
    return {count64(counters, COUNTER_WALK_GROUP_STEPS), count64(counters, COUNTER_WALK_LANE_STEPS),
            count64(counters, COUNTER_WALK_TREES), counters[COUNTER_SUBGROUP_SIZE]};
}

std::vector<RowBand> readBackBands(int width, int height, std::size_t bytesPerPixel, std::size_t maxBytes) {
    std::vector<RowBand> bands;
    if (width <= 0 || height <= 0) return bands;
    const std::size_t rowBytes = std::size_t(width) * bytesPerPixel;
    const int perBand = static_cast<int>(std::clamp<std::size_t>(maxBytes / std::max<std::size_t>(rowBytes, 1), 1,
                                                                 std::size_t(height)));
    for (int y = 0; y < height; y += perBand) bands.push_back({y, std::min(perBand, height - y)});
    return bands;
}

Accumulators Renderer::readAccumulators() const {
    Accumulators a;
    a.width = m_width;
    a.height = m_height;
    const size_t n = static_cast<size_t>(m_width) * m_height;
    a.sum.resize(n);
    a.sumSq.resize(n);
    a.albedo.resize(n);
    a.normal.resize(n);
    // In bands of rows: one call's byte count is a GLsizei (readBackBands).
    for (const RowBand& band : readBackBands(m_width, m_height, sizeof(glm::vec4))) {
        const size_t offset = size_t(band.y0) * size_t(m_width);
        const auto bytes = static_cast<GLsizei>(size_t(band.rows) * size_t(m_width) * sizeof(glm::vec4));
        for (const auto& [texture, out] : {std::pair{m_accum, &a.sum}, std::pair{m_accumSq, &a.sumSq},
                                           std::pair{m_albedo, &a.albedo}, std::pair{m_normal, &a.normal}})
            glGetTextureSubImage(texture, 0, 0, band.y0, 0, m_width, band.rows, 1, GL_RGBA, GL_FLOAT, bytes,
                                 out->data() + offset);
    }
    return a;
}

Film Renderer::readFilm() const { return resolveFilm(readAccumulators()); }

}  // namespace caustic
