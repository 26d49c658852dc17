// Scene-specialised configurations of the same source: which kinds of material, light, shape,
// environment, sampler and light selection the shaders must handle. Each CAUSTIC_* below is a
// bitmask over the corresponding constants of shared/layout.h (bit MAT_DIFFUSE of
// CAUSTIC_MATERIALS, and so on); left undefined it is every kind, which is the general program
// (the test kernels, and the integrator where specialisation is off). The renderer defines them
// from the scene it renders (renderer/renderer_programs.cpp, featureDefines) when it specialises: on
// llvmpipe by default. Code for a kind the scene lacks is then constant-false and the compiler
// removes it.
//   Why: llvmpipe runs 8 invocations as the lanes of a SIMD register, and Mesa 22.3's executes
//   *both* sides of every branch (under a lane mask), every loop at least once, whatever the data;
//   a branch no invocation takes costs as much as one they all take (Mesa 25's skips code no lane
//   needs; specialisation still pays there, docs/performance.md). So the general integrator paid, at every
//   vertex, for every BSDF model, every light type, the sphere test beside each quad test, the
//   texture lookups, the environment and both samplers. docs/performance.md has the figures.
// Where a kind is present its code is the general code: a specialised program computes the same
// numbers as the general one for the scenes it is built for.
#ifndef SCENE_FEATURES_GLSL
#define SCENE_FEATURES_GLSL

#ifndef CAUSTIC_MATERIALS
#define CAUSTIC_MATERIALS 0xffffffffu      // bits MAT_*
#endif
#ifndef CAUSTIC_LIGHTS
#define CAUSTIC_LIGHTS 0xffffffffu         // bits LIGHT_*
#endif
#ifndef CAUSTIC_SHAPES
#define CAUSTIC_SHAPES 0xffffffffu         // bits PRIM_*, and SHAPE_BIT_MESH for mesh instances
#endif
#ifndef CAUSTIC_ENVIRONMENTS
#define CAUSTIC_ENVIRONMENTS 0xffffffffu   // bits ENV_*
#endif
#ifndef CAUSTIC_SAMPLERS
#define CAUSTIC_SAMPLERS 0xffffffffu       // bits SAMPLER_*
#endif
#ifndef CAUSTIC_LIGHT_SELECTIONS
#define CAUSTIC_LIGHT_SELECTIONS 0xffffffffu  // bits LIGHT_SELECT_*
#endif
#ifndef CAUSTIC_TEXTURES
#define CAUSTIC_TEXTURES 1u                // 0: no material has a texture
#endif
#ifndef CAUSTIC_EMISSION_TEXTURES
#define CAUSTIC_EMISSION_TEXTURES 1u       // 0: no material has an emission texture
#endif
#ifndef CAUSTIC_ALPHA_MASK
#define CAUSTIC_ALPHA_MASK 1u              // 0: no mesh has an alpha-masked material (geometry/alpha_mask.glsl)
#endif
#ifndef CAUSTIC_MEDIA
#define CAUSTIC_MEDIA 63u                  // bits MEDIA_*: what the scene's media need (integrator/medium.glsl)
#endif
#ifndef CAUSTIC_CAMERA
#define CAUSTIC_CAMERA 3u                  // bits CAMERA_*: what the camera needs (integrator/camera.glsl)
#endif
#ifndef CAUSTIC_SINGLE_LIGHT
#define CAUSTIC_SINGLE_LIGHT 0u            // 1: exactly one light (the environment may be it)
#endif
#ifndef CAUSTIC_TRAVERSAL
#define CAUSTIC_TRAVERSAL 0u               // 0: chosen per scene at run time, 1: test every primitive, 2: the BVH
#endif

#define SHAPE_BIT_MESH 16u
#define HAS_MATERIAL(t) ((CAUSTIC_MATERIALS & (1u << (t))) != 0u)
#define HAS_LIGHT(t) ((CAUSTIC_LIGHTS & (1u << (t))) != 0u)
#define HAS_SHAPE(t) ((CAUSTIC_SHAPES & (1u << (t))) != 0u)
#define HAS_MESHES ((CAUSTIC_SHAPES & (1u << SHAPE_BIT_MESH)) != 0u)
#define HAS_ENVIRONMENT(t) ((CAUSTIC_ENVIRONMENTS & (1u << (t))) != 0u)
#define HAS_ANY_ENVIRONMENT ((CAUSTIC_ENVIRONMENTS & ~(1u << ENV_NONE)) != 0u)
#define HAS_SAMPLER(t) ((CAUSTIC_SAMPLERS & (1u << (t))) != 0u)
#define HAS_LIGHT_SELECTION(t) ((CAUSTIC_LIGHT_SELECTIONS & (1u << (t))) != 0u)
#define HAS_MEDIA(bits) ((CAUSTIC_MEDIA & (bits)) != 0u)
#define HAS_CAMERA(bits) ((CAUSTIC_CAMERA & (bits)) != 0u)
// Whether kind `t` is the only one of its mask (a test of the run-time value can go).
#define ONLY_KIND(mask, t) ((mask) == (1u << (t)))

#endif
