// The path tracer on the GPU: owns the integrator program, the scene buffers and the
// accumulation images. Needs a current OpenGL 4.5 context (headless EGL or the editor's window).
#pragma once

#include "renderer/dirty.h"
#include "renderer/film.h"
#include "renderer/gpu_limits.h"
#include "renderer/gpu_scene.h"
#include "renderer/integrator_config.h"
#include "renderer/lens.h"
#include "renderer/program_builder.h"
#include "renderer/scene.h"
#include "renderer/shader_loader.h"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace caustic {

// Reading an image back takes a GLsizei (32-bit) byte count, so a film larger than 2^31 bytes
// (134 M RGBA float pixels, inside the 16384x16384 render limit) is read in bands of whole rows,
// each at most maxBytes: the first row and the row count of each, covering [0, height) in order.
// A rectangle of pixels [x0, x1) x [y0, y1) of the image, row 0 at the top.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct RowBand {
    int y0 = 0, rows = 0;
};
inline constexpr std::size_t kMaxReadBackBytes = std::size_t(1) << 30;
std::vector<RowBand> readBackBands(int width, int height, std::size_t bytesPerPixel,
                                   std::size_t maxBytes = kMaxReadBackBytes);

// What the mesh walks did (IntegratorConfig::walkStats; shaders/shared/layout.h, COUNTER_WALK_*): the
// walk loops' iterations as the SIMD groups ran them and as their lanes took part in them (the
// lanes were busy laneSteps / (groupSteps * subgroupSize) of the time paid), and the instance
// trees walked.
struct WalkStats {
    std::uint64_t groupSteps = 0, laneSteps = 0, trees = 0;
    std::uint32_t subgroupSize = 0;
};

class Renderer {
public:
    // Compiles shaders/integrator/path.comp from shaderDir, configured by `config` (its unset
    // choices take the current device's defaults). On failure returns null with the compiler's
    // messages mapped to file:line.
    static std::unique_ptr<Renderer> create(const std::string& shaderDir, const IntegratorConfig& config,
                                            std::string* error);
    // The configuration it runs with, every choice made.
    const ResolvedIntegratorConfig& config() const { return m_config; }
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // How files named by scenes (environment maps, textures) are read; without one, a scene
    // that names a file fails to compile with a clear message.
    // Reads are cached by path and file time, so an edit that recompiles the scene (a material
    // slider, a transform drag) does not read its textures and environment map again.
    void setImageReader(ImageReader reader);

    // Compiles and uploads the scene (resolution, seed, depth come from scene.render) and
    // restarts accumulation.
    bool setScene(const Scene& scene, std::string* error);

    // Applies an edited scene, redoing only what `dirty` names (camera and settings: nothing to
    // upload; materials: the material table; transforms: the top level of the BVH, instances and
    // lights, never a mesh's BVH; anything else: recompile, reusing cached meshes), and restarts
    // accumulation.
    bool update(const Scene& scene, std::uint32_t dirty, std::string* error);

    // The accumulation image (RGBA32F: rgb = sum of samples, a = sample count) for display.
    unsigned accumulationTexture() const { return m_accum; }

    // STRATEGY_MIS (default), STRATEGY_LIGHT_ONLY or STRATEGY_BSDF_ONLY; restarts accumulation.
    void setStrategy(std::uint32_t strategy);

    void resetAccumulation();

    // Parts of a split render (the farm; docs/farm.md). The samples rendered get indices from
    // `base` on (render(n) after it renders [base, base + n)), so a part renders exactly the
    // samples of a whole render's range. Takes effect with the next dispatch.
    void setSampleBase(std::uint32_t base) { m_sampleBase = base; }
    std::uint32_t sampleBase() const { return m_sampleBase; }
    // Renders only this rectangle of the scene's image (clamped to it; an empty one: all of it):
    // the accumulation images, readFilm() and readAccumulators() are the crop's size, and each
    // pixel gets the same camera ray and random numbers as in the whole image. Takes effect with
    // the next setScene().
    void setCrop(const PixelRect& crop) { m_crop = crop; }
    PixelRect region() const { return m_region; }   // what the accumulation images hold

    // Adds `count` samples per pixel. Work is split into short dispatches (adapted to the
    // measured speed) with at most two in flight, so the driver never holds a long queue.
    // progress(samplesDone) is called after each completed dispatch.
    void render(int count, const std::function<void(int)>& progress = {});

    // What renderFor did.
    struct Progress {
        int samplesCompleted = 0;       // whole samples of every pixel finished by this call
        long long pixelSamples = 0;     // pixel-samples rendered (part of a sample counts its pixels)
        double seconds = 0.0;           // wall time, including waiting for the GPU
    };
    // Renders for about `budgetSeconds`, at most `maxSamples` whole samples, for an interactive
    // caller that must return in time (the editor's frame): whole samples of the image while one
    // fits the budget, else one sample over a run of the kernel's 8x8 tiles (row by row),
    // continuing where the previous call stopped, sized from the measured cost so that the call
    // takes about the budget. A sample counts in samplesDone() once every tile has it; the accumulation image holds per-pixel
    // counts (alpha), so a display of a half-finished sample is still correct. The same pixels,
    // sample indices and seed are rendered as by render(): the image does not depend on how the
    // work was split.
    Progress renderFor(double budgetSeconds, int maxSamples);
    bool bandInProgress() const { return m_bandTile > 0; }
    std::uint32_t tileCount() const;   // the integrator's 8x8 tiles in the image
    // How much of the next sample renderFor has done (0 when none is under way), in [0, 1).
    float bandProgress() const { return m_bandTile > 0 ? float(m_bandTile) / float(tileCount()) : 0.0f; }

    int samplesDone() const { return m_samplesDone; }
    std::uint64_t droppedSamples() const;
    std::uint64_t raysTraced() const;      // since the last restart of accumulation
    // The mesh walks' statistics since the last restart of accumulation: zeros unless the
    // integrator was built with them (IntegratorConfig::walkStats).
    WalkStats walkStats() const;

    // Binds the frame constants (for samples [firstSample, firstSample + samples)) and the scene
    // buffers at their shared binding points; the integrator and test kernels both use it.
    void bindScene(std::uint32_t firstSample, std::uint32_t samples);
    // The same for the integrator's 8x8 tiles [tile0, tile1) only, numbered row by row
    // (frame.dispatch.z, w).
    void bindScene(std::uint32_t firstSample, std::uint32_t samples, std::uint32_t tile0, std::uint32_t tile1);
    Film readFilm() const;
    Accumulators readAccumulators() const;   // the sums as they are (part files)
    const CompiledScene& compiled() const { return m_compiled; }
    // The scene it renders: the last one setScene or update accepted.
    const Scene& scene() const { return m_scene; }
    // The camera's lens system as the shader traces it (null when the camera has none).
    const LensCamera* lensCamera() const { return m_lensCamera.get(); }
    // The imported meshes and their BVHs kept between compiles: the editor inserts meshes it
    // prepared off-thread (prepareMesh) before the edit that uses them. Same thread as update().
    MeshCache& meshCache() { return m_meshCache; }
    unsigned countersBuffer() const { return m_counters; }  // bound at BINDING_COUNTERS by bindScene
    // The feature defines (shaders/scene/features.glsl) of the program specialised for the current
    // scene and settings, whether or not this renderer specialises (test kernels build with them).
    ShaderDefines featureDefines() const;
    // Whether a specialised program may hold the scene's primitives as constants (a scene of a
    // few analytic primitives and no mesh: CAUSTIC_BAKED_PRIMITIVES, renderer_programs.cpp
    // bakedPrimitiveTests): 1.8x on llvmpipe for the Cornell box, but every change of geometry
    // then builds a new program (about a second on llvmpipe). For renders whose geometry stays
    // put (batch mode, caustic-bench), not for the editor. Off by default; without
    // specialisation it does nothing. IntegratorConfig::bakeGeometry, where set, overrides it.
    void setBakeGeometry(bool bake) { m_bakeGeometry = bake; }
    // The integrator the last dispatch used (before any: the general one, built if need be).
    unsigned program();
    // Whether that is the general program standing in for the scene's own, which failed to build
    // (selectProgram; the reason went to stderr): the image is right but slower, so a benchmark
    // must not report its figures as the scene program's (caustic-bench marks the row FALLBACK).
    bool programFellBack() const { return m_programFellBack; }
    // Deferred builds (the editor): setScene and update leave the integrator program the scene
    // needs to the first dispatch, so a window can show "Building shaders" before the frame that
    // builds it (a build blocks for seconds on llvmpipe, whose glLinkProgram compiles even with
    // GL_KHR_parallel_shader_compile). programPending(): the next dispatch builds a program.
    void setDeferredProgramBuilds(bool on) { m_deferBuilds = on; }
    bool programPending() const;
    // Builds in the background (the editor; renderer/program_builder.h): the integrator programs
    // are built on the builder's thread, and a dispatch that needs one not built yet returns at once,
    // rendering with a stand-in that renders the scene right (standInProgram), else rendering
    // nothing (the accumulated image stays). Implies deferred builds. Null: built here.
    void setProgramBuilder(std::shared_ptr<ProgramBuilder> builder);
    bool buildsInBackground() const { return m_builder != nullptr; }
    // The last dispatch found the scene's program still building in the background: with nothing
    // to stand in for it (nothing rendered), or with a stand-in that rendered (standInProgram).
    bool waitingForBuild() const { return m_waitingForBuild && m_program == 0; }
    bool standingIn() const { return m_waitingForBuild && m_program != 0; }
    // Why the last dispatch rendered nothing: no integrator program builds (with deferred builds
    // this is where a source that does not compile shows); empty after a dispatch that rendered.
    const std::string& programError() const { return m_programError; }
    // Builds the general program now (create() does only where it renders): the check that the
    // whole source compiles, for a shader reload that must keep the last working shaders.
    bool checkSource(std::string* error) { return generalProgram(error) != 0; }

    // The GL limits scenes are checked against before upload (renderer/gpu_limits.h), queried
    // from the context by create(); tests inject smaller ones.
    const GpuLimits& limits() const { return m_limits; }
    void setLimits(const GpuLimits& limits) { m_limits = limits; }

private:
    Renderer() = default;
    // Compiles and checks against m_limits; on failure m_compiled still holds the last good scene.
    bool compileChecked(const Scene& scene, CompiledScene* out, std::string* error);
    // meshes = false: all but the meshes' data, already there. Returns the GL errors the uploads
    // raised (empty: none).
    std::string upload(bool meshes = true);
    void dispatch(std::uint32_t firstSample, std::uint32_t samples, std::uint32_t tile0 = 0, std::uint32_t tile1 = ~0u);
    double finishBand();   // renders the rest of a started sample (renderFor); returns seconds
    long long tilePixels(std::uint32_t tile0, std::uint32_t tile1) const;
    PixelRect cropOf(const Scene& scene) const;   // m_crop within the scene's image
    // The camera's lens system (renderer/lens.h), prepared for `scene` (read, focused, stopped
    // down, its pupil bounds traced) when its lens, focus, stop, film or image size changed since
    // the last; an empty block without a lens. False with a message naming camera.lens and the file.
    bool prepareLens(const Scene& scene, std::string* error);

    // Makes m_program the one for the current scene and settings (compiling it the first time),
    // or the general one if that fails; called where the scene changes, and before each dispatch.
    // False (m_program 0) with the compiler's message when neither builds.
    bool selectProgram(std::string* error);
    // selectProgram before rendering: false (reported once on stderr, kept in m_programError)
    // when no program builds, so nothing is dispatched and no sample counted.
    bool programReady();
    // The program without feature defines, compiled the first time; 0 with the compiler's message.
    // pending: built in the background (buildProgram).
    unsigned generalProgram(std::string* error, bool* pending = nullptr);
    // Whether the general program renders the current scene as its own would: the general one
    // leaves out alpha masks and the media of surface parts and random walks (kGeneralMedia).
    bool generalRendersScene() const;
    // What renders while the scene's program is built in the background: the general program where
    // it is built and renders the scene right, else none (0).
    unsigned standInProgram() const;
    // The program of `file` with these defines, compiled the first time; 0 with the compiler's
    // message. With pending (and a builder), one not built yet is asked of the builder (once) and
    // 0 returned with *pending true until it is done.
    unsigned buildProgram(const std::string& file, const ShaderDefines& defines, std::string* error,
                          bool* pending = nullptr);

    // The builds asked of the builder other than the one for wantedKey: finished ones kept (or
    // their failures).
    void settleBuilds(const std::string& wantedKey);

    std::string m_shaderDir;
    ResolvedIntegratorConfig m_config;
    bool m_specialize = false;   // build the integrator per scene (featureDefines in renderer_programs.cpp)
    bool m_bakeGeometry = false; // setBakeGeometry
    std::map<std::string, unsigned> m_programs;  // by their defines
    std::map<std::string, std::string> m_programFailures;  // the compiler's message, by the same keys
    unsigned m_general = 0;      // the program without feature defines (but CAUSTIC_ALPHA_MASK 0: renderer_programs.cpp, generalDefines)
    unsigned m_program = 0;      // the one the last dispatch used
    bool m_programFellBack = false;  // programFellBack
    bool m_deferBuilds = false;
    std::shared_ptr<ProgramBuilder> m_builder;   // setProgramBuilder
    std::map<std::string, std::shared_ptr<ProgramBuilder::Build>> m_building;   // asked of it, by key
    bool m_waitingForBuild = false;   // waitingForBuild
    ShaderDefines selectedDefines() const;   // the defines selectProgram asks for first
    std::string m_fallbackReason;    // the failure the last fallback reported (on stderr, once)
    std::string m_programError;  // the last dispatch's failure to build one, reported once
    unsigned m_accum = 0, m_accumSq = 0;
    unsigned m_albedo = 0, m_normal = 0;   // the AOVs: sums of the first non-specular albedo and normal
    std::array<std::uint32_t, COUNTER_WORDS> readCounters() const;  // the counter buffer's words
    unsigned m_frameUbo = 0, m_primitives = 0, m_materials = 0, m_lights = 0, m_tables = 0, m_counters = 0;
    unsigned m_lightTree = 0;    // GpuLightNode[] (CompiledScene::lightTree)
    unsigned m_lensUbo = 0;      // LensBlock (lensUniformBlock; zeros without a lens system)
    std::string m_lensKey;       // what the block was prepared from ("" : no lens)
    std::shared_ptr<const LensCamera> m_lensCamera;  // the prepared lens system, or null
    unsigned m_envTexture = 0;   // m_tables holds all the CDF tables (packTables)
    // Geometry: BVH nodes, top-level entries, instances, triangles, vertices.
    static constexpr int kGeometryBuffers = 5;
    unsigned m_geometry[kGeometryBuffers] = {};
    unsigned m_texels = 0, m_textures = 0, m_bsdfTables = 0;  // material textures, GGX albedo table
    // Buffer textures over primitives, BVH nodes (binary and 4-wide), triangles, vertices,
    // top-level entries, instances, materials, the primitives' hit records, lights, the light tree,
    // the CDF tables and the BSDF tables (TEXUNIT_*; bindScene attaches them).
    static constexpr int kTexelViews = 13;
    unsigned m_wideNodes = 0;      // GpuWideBvhNode[]: the meshes' 4-wide BVHs (geometry/walk_wide4.glsl)
    unsigned m_primitiveHits = 0;  // GpuPrimitive[]: the ray tests' form (primitiveHitRecords)
    unsigned m_texelViews[kTexelViews] = {};
    bool m_imageLoads = false;     // the views are also bound as images (enough image units; CAUSTIC_IMAGE_LOADS)
    ImageReader m_readImage;
    GpuLimits m_limits;
    MeshCache m_meshCache;      // imported meshes and their BVHs, reused across edits
    int m_width = 0, m_height = 0;     // the accumulation images: the crop's size
    PixelRect m_crop, m_region;        // asked for; rendered (the crop within the image)
    std::uint32_t m_sampleBase = 0;    // the index of the first sample (setSampleBase)
    Scene m_scene;
    CompiledScene m_compiled;
    std::uint32_t m_strategy = STRATEGY_MIS;
    int m_samplesDone = 0;
    bool m_uploaded = false;           // a scene has been uploaded (the buffers hold its data)
    double m_secondsPerSample = 0.0;   // measured, for sizing dispatches
    double m_secondsPerPixelSample = 0.0;   // measured by renderFor, for sizing runs of tiles
    std::uint32_t m_bandTile = 0;      // > 0: tiles [0, m_bandTile) have sample m_samplesDone already
};

}  // namespace caustic
