// Struct layouts shared by C++ and GLSL (std430 storage buffers, std140 uniform block).
// Compiled by both: C++ sees glm types inside namespace caustic::gpu, GLSL sees its own types.
// Rules (style.md): vec4 / uvec4 and scalars only, sizes multiple of 16, no bool / vec3 arrays.
// C++ static_asserts the sizes (renderer/gpu_scene.cpp); a GPU test compares the offsets the
// driver reports with offsetof.
#ifndef CAUSTIC_SHARED_LAYOUT_H
#define CAUSTIC_SHARED_LAYOUT_H

#ifdef __cplusplus
#include <glm/glm.hpp>
#include <cstdint>
namespace caustic::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uint = std::uint32_t;
#define CAUSTIC_STRUCT(name) struct alignas(16) name
#else
#define CAUSTIC_STRUCT(name) struct name
#endif

// Each struct is one list of 16-byte rows, GPU_<NAME>_ROWS(V4, U4, V3U, UUUU), from which its
// declaration (here), its texel loader (scene/buffers.glsl, GPU_TEXEL_LOADER), its size check
// (renderer/gpu_scene.cpp) and its layout test (tests/gpu/test_layout.cpp) are generated. A row
// is one of V4(name): a vec4; U4(name): a uvec4; V3U(v, u): a vec3 and a uint; UUUU(a, b, c, d):
// four uints. A new member goes into the list and nowhere else.
#define GPU_DECLARE_V4(n) vec4 n;
#define GPU_DECLARE_U4(n) uvec4 n;
#define GPU_DECLARE_V3U(v, u) vec3 v; uint u;
#define GPU_DECLARE_UUUU(a, b, c, d) uint a; uint b; uint c; uint d;
#define GPU_DECLARE(ROWS) ROWS(GPU_DECLARE_V4, GPU_DECLARE_U4, GPU_DECLARE_V3U, GPU_DECLARE_UUUU)
// The number of rows (texels) of a struct, as a uint expression.
#define GPU_COUNT_1(a) + 1u
#define GPU_COUNT_2(a, b) + 1u
#define GPU_COUNT_4(a, b, c, d) + 1u
#define GPU_ROW_COUNT(ROWS) (0u ROWS(GPU_COUNT_1, GPU_COUNT_1, GPU_COUNT_2, GPU_COUNT_4))

// Binding points (shared constants, never magic numbers).
#define BINDING_ACCUM_IMAGE 0      // image2D rgba32f: rgb = sum of samples, a = sample count
#define BINDING_ACCUM_SQ_IMAGE 1   // image2D rgba32f: rgb = sum of squared samples
#define BINDING_ALBEDO_IMAGE 2     // image2D rgba32f: rgb = sum of first non-specular albedos, a = count
#define BINDING_NORMAL_IMAGE 3     // image2D rgba32f: rgb = sum of first non-specular world normals, a = count
#define BINDING_FRAME_UBO 0
#define BINDING_LENS_UBO 1         // LensBlock (uniform-block bindings are numbered apart from the storage buffers below): a lens system camera's surfaces and exit-pupil bounds (integrator/lens_camera.glsl)
#define LENS_MAX_SURFACES 32       // renderer/lens.h, kLensMaxSurfaces
#define LENS_PUPIL_BINS 64         // renderer/lens.h, kLensPupilBins
// What a camera needs beyond the thin lens (bits of CAUSTIC_CAMERA, scene/features.glsl).
#define CAMERA_LENS_SYSTEM 1u      // a lens system (LensBlock)
#define CAMERA_APERTURE_IMAGE 2u   // an aperture image (GpuFrame::aperture)
#define BINDING_PRIMITIVES 1
#define BINDING_MATERIALS 2
#define BINDING_LIGHTS 3
#define BINDING_TABLES 4           // float[]: the scene's CDF tables, one after another (GpuFrame::tables)
#define BINDING_COUNTERS 5
#define BINDING_LIGHT_TREE 6       // GpuLightNode[]: the light tree (renderer/light_tree.h), root at 0
#define BINDING_TEST_OUTPUT 7      // test kernels only
#define TEXUNIT_ENV_MAP 0          // sampler2D: the environment map (RGB radiance)
// Buffer textures over the scene's storage buffers (usamplerBuffer), read instead of the buffers
// when CAUSTIC_FETCH_TEXELS is defined (scene/buffers.glsl). Each view's format is here and only
// here, as TEXUNIT_<name>_FORMAT, the GLSL image format's name: scene/buffers.glsl puts it in the
// image declaration, renderer_dispatch.cpp (bindScene) turns it into the GL format the view is made and
// bound with (an image's format qualifier must be the view's own format).
#define TEXUNIT_PRIMITIVES 1
#define TEXUNIT_PRIMITIVES_FORMAT rgba32ui
#define TEXUNIT_BVH_NODES 2
#define TEXUNIT_BVH_NODES_FORMAT rgba32ui
#define TEXUNIT_TRIANGLES 3
#define TEXUNIT_TRIANGLES_FORMAT rgba32ui
#define TEXUNIT_TLAS_REFS 4        // one top-level entry a texel
#define TEXUNIT_TLAS_REFS_FORMAT r32ui
#define TEXUNIT_INSTANCES 5
#define TEXUNIT_INSTANCES_FORMAT rgba32ui
#define TEXUNIT_MATERIALS 6
#define TEXUNIT_MATERIALS_FORMAT rgba32ui
#define TEXUNIT_PRIMITIVE_HITS 7
#define TEXUNIT_PRIMITIVE_HITS_FORMAT rgba32ui
#define TEXUNIT_WIDE_NODES 8       // GpuWideBvhNode[] (geometry/walk_wide4.glsl; no storage-buffer form)
#define TEXUNIT_WIDE_NODES_FORMAT rgba32ui
#define TEXUNIT_VERTICES 9         // GpuVertex[]
#define TEXUNIT_VERTICES_FORMAT rgba32ui
#define TEXUNIT_TABLES 10          // the CDF tables (sceneTables), one float a texel
#define TEXUNIT_TABLES_FORMAT r32ui
#define TEXUNIT_LIGHTS 11          // GpuLight[]
#define TEXUNIT_LIGHTS_FORMAT rgba32ui
#define TEXUNIT_LIGHT_TREE 12      // GpuLightNode[]
#define TEXUNIT_LIGHT_TREE_FORMAT rgba32ui
#define TEXUNIT_BSDF_TABLES 13     // the BSDF tables (bsdfTables), one float a texel
#define TEXUNIT_BSDF_TABLES_FORMAT r32ui
// With CAUSTIC_IMAGE_LOADS the same views are bound as read-only image buffers (uimageBuffer) at image
// unit IMAGE_UNIT_TEXELS + their texture unit (scene/buffers.glsl), after the film's images.
#define IMAGE_UNIT_TEXELS 4
// The highest TEXUNIT_*: at most 15, so that the units fit the 16 GL guarantees a compute shader
// (GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS >= 16); a view beyond that needs the limit checked.
#define TEXUNIT_LAST TEXUNIT_BSDF_TABLES
// A leaf's word in the 4-wide nodes: LEAF_BIT | count << LEAF_COUNT_SHIFT | first (count in
// [1, LEAF_MAX_COUNT], first <= LEAF_MAX_FIRST).
#define LEAF_BIT 0x80000000u
#define LEAF_COUNT_SHIFT 27u
#define LEAF_MAX_COUNT 15u
#define LEAF_MAX_FIRST ((1u << LEAF_COUNT_SHIFT) - 1u)
#define BINDING_PRIMITIVE_HITS 8   // GpuPrimitive[]: what the ray tests read (quads in plane form; renderer/renderer.cpp)
#define BINDING_TEXELS 9           // uvec2[]: every material texture's texels (mip chains), RGBA as 4 halves
#define BINDING_TEXTURES 10        // GpuTexture[]: where each texture's texels are
#define BINDING_BVH_NODES 13       // BvhNode[]: the top-level BVH at 0, then every mesh's BVH
#define BINDING_TLAS_REFS 14       // uint[]: top-level leaf entries: primitive index, or TLAS_REF_INSTANCE | instance
#define BINDING_INSTANCES 15       // GpuInstance[]: mesh instances
#define BINDING_TRIANGLES 16       // GpuTriangle[]: every mesh's triangles, in its BVH's leaf order
#define BINDING_VERTICES 17        // GpuVertex[]: every mesh's shading attributes
#define BINDING_BSDF_TABLES 11
// The integrator's dispatch interleaves its tiles over this many bands (integrator/path.comp):
// it dispatches DISPATCH_STRIDES * ceil(tiles / DISPATCH_STRIDES) work groups.
#define DISPATCH_STRIDES 64u     // float[]: the BSDF tables (GGX albedo, then the surface model's; BSDF_TABLE_*)

// Words of the counter buffer.
#define COUNTER_DROPPED 0          // samples dropped because they were NaN or infinite
#define COUNTER_RAYS_LO 1          // rays traced, low 32 bits
#define COUNTER_RAYS_HI 2          // rays traced, high 32 bits
// The mesh walks' statistics (CAUSTIC_WALK_STATS, a benchmark aid; caustic-bench prints them), each
// a 64-bit count in two words (low, high): iterations of a walk's loop as its SIMD groups run
// them (one per group and iteration, whichever of its lanes take part), the same summed over the
// lanes that take part, and the instance trees whose walk began.
#define COUNTER_WALK_GROUP_STEPS 3
#define COUNTER_WALK_LANE_STEPS 5
#define COUNTER_WALK_TREES 7
#define COUNTER_SUBGROUP_SIZE 9    // the lanes of a SIMD group (gl_SubGroupSizeARB), with the statistics
#define COUNTER_WORDS 10

// Primitive types.
#define PRIM_SPHERE 0u
#define PRIM_QUAD 1u

// Primitive flags (GpuPrimitive::info.w).
#define PRIM_FLAG_ONE_SIDED_EMITTER 1u  // emits from its front face only (rect lights unless two-sided,
                                        // objects with their own emission unless two_sided); also in
                                        // GpuInstance::info2.w for meshes
#define PRIM_FLAG_ALPHA_MASK 2u         // GpuInstance::info2.w: some material of the mesh has
                                        // MAT_FLAG_ALPHA_MASK (geometry/alpha_mask.glsl)

// Material types (GpuMaterial::info.x); the models are in shaders/bsdf/, one per file.
#define MAT_DIFFUSE 0u              // Lambert
#define MAT_OREN_NAYAR 1u           // qualitative Oren-Nayar (optionally compensated)
#define MAT_EON 2u                  // energy-preserving Oren-Nayar (Portsmouth et al. 2025)
#define MAT_MIRROR 3u               // perfect mirror (delta)
#define MAT_TRANSMISSION 4u         // perfect transmission (delta)
#define MAT_DIELECTRIC 5u           // smooth glass (two delta lobes)
#define MAT_ROUGH_DIELECTRIC 6u     // GGX microfacet glass
#define MAT_CONDUCTOR 7u            // smooth conductor (delta, complex Fresnel)
#define MAT_ROUGH_CONDUCTOR 8u      // GGX microfacet conductor
#define MAT_SURFACE 9u              // layered surface: sheen over coat over metal / specular + diffuse (surface.glsl)
#define MAT_VOLUME 10u              // no surface: an index-matched boundary of the medium inside (integrator/medium.glsl)
#define MAT_THIN_DIELECTRIC 11u     // a thin dielectric sheet: reflection and straight-through transmission (thin.glsl)
#define MAT_DIFFUSE_TRANSMISSION 12u  // a thin diffuse sheet: Lambertian reflection and transmission (thin.glsl)

// Material flags (GpuMaterial::info.y).
#define MAT_FLAG_ENERGY_COMPENSATION 1u  // Oren-Nayar: the global factor; rough conductor: multiple scattering
#define MAT_FLAG_FRESNEL_ONE 2u          // conductor with F = 1 (the "perfect" metal)
#define MAT_FLAG_NO_REFLECTION 4u        // rough dielectric: transmission only (rough "transmission"):
                                         // F = 0 where light can refract, 1 under total internal reflection
#define MAT_FLAG_METAL_TEXTURE 8u        // surface: the roughness texture's G channel is the metalness
#define MAT_FLAG_ALPHA_MASK 16u          // cut-outs: rays pass where the albedo texture's alpha is below
                                         // uintBitsToFloat(info.z) (geometry/alpha_mask.glsl)
#define MAT_FLAG_MEDIUM 32u              // dielectric, volume: its interior is a medium, sigma_a = k.rgb,
                                         // sigma_s = eta.rgb, Henyey-Greenstein g = eta.w (integrator/medium.glsl)
#define MAT_FLAG_TRANSMISSION_PART 64u   // surface: its transmission is the material at index info.w (a
                                         // dielectric with the interior medium, or a thin dielectric)
#define MAT_FLAG_SUBSURFACE_PART 128u    // surface: its subsurface is the material after the transmission
                                         // part (at info.w without one): a dielectric whose interior is
                                         // walked (MAT_FLAG_RANDOM_WALK), or a thin diffuse transmitter
#define MAT_FLAG_RANDOM_WALK 256u        // dielectric with MAT_FLAG_MEDIUM: a subsurface interior, walked
                                         // without light sampling and outside the depth budget

// What the scene's media need of the integrator (CAUSTIC_MEDIA, bits; scene/features.glsl).
#define MEDIA_ABSORBING 1u          // some medium (a material's interior or the scene's) absorbs or scatters
#define MEDIA_SCATTERING 2u         // some medium scatters: free-flight sampling, medium vertices
#define MEDIA_BOUNDARIES 4u         // some material is MAT_VOLUME: rays and shadow rays cross its surfaces
#define MEDIA_NESTED 8u             // some dielectric or volume has a nesting priority (GpuMaterial::info.w)
#define MEDIA_SURFACE_PARTS 16u     // some surface has a transmission or subsurface part (integrator/surface_parts.glsl)
#define MEDIA_RANDOM_WALK 32u       // some interior is a subsurface random walk (MAT_FLAG_RANDOM_WALK)

#define GGX_ALBEDO_TABLE_SIZE 32    // the GGX albedo table is 32 (mu) x 32 (alpha)
// The BSDF tables buffer (BINDING_BSDF_TABLES), computed on the GPU from the shaders' own code
// (renderer/bsdf_tables.cpp): offsets in floats. N = GGX_ALBEDO_TABLE_SIZE entries per mu, alpha
// and sheen-roughness axis, SURFACE_TABLE_IOR slices in (ior - 1) / (ior + 1) over ior [1, 3].
#define SURFACE_TABLE_IOR 16
#define BSDF_TABLE_GGX 0                                   // E(mu, alpha), F = 1 GGX: N x N
#define BSDF_TABLE_DIELECTRIC 1024                         // E(mu, alpha, ior), GGX reflection x Fresnel: N x N x I
#define BSDF_TABLE_DIELECTRIC_AVG (1024 + 1024 * 16)      // 2 int E mu dmu (alpha, ior): N x I
#define BSDF_TABLE_SHEEN (BSDF_TABLE_DIELECTRIC_AVG + 32 * 16)  // E(mu, r), the sheen lobe: N x N
#define BSDF_TABLE_FLOATS (BSDF_TABLE_SHEEN + 1024)

#define BVH_BRUTE_FORCE_MAX 32u  // scenes of at most this many analytic primitives and no mesh skip the tree
#define TLAS_REF_INSTANCE 0x80000000u

// Light types.
#define LIGHT_RECT 0u
#define LIGHT_SPHERE 1u
#define LIGHT_POINT 2u
#define LIGHT_SPOT 3u
#define LIGHT_ENV 4u
#define LIGHT_MESH 5u

// Light flags.
#define LIGHT_FLAG_TWO_SIDED 1u     // area lights (rect, sphere, mesh): emits from the back faces too
#define LIGHT_FLAG_LINEAR_ANGLE 2u  // spot: falls off linearly in the angle (Mitsuba's), not smoothstep in cos
#define LIGHT_FLAG_EMISSION_TEXTURE 4u  // rect, sphere, mesh: a material's emission texture scales the
                                        // radiance per point (bsdf/material.glsl, materialEmission)

#define LIGHT_TREE_LEAF 0x80000000u // GpuLightNode::info.x: a leaf; the light index is info.x & ~LIGHT_TREE_LEAF

// Light selection (GpuFrame::sampling.y): how next event estimation picks a light.
#define LIGHT_SELECT_TREE 0u        // the light tree, by importance at the shading point (default)
#define LIGHT_SELECT_POWER 1u       // one global CDF by power
#define LIGHT_SELECT_UNIFORM 2u     // every light equally

// Samplers (GpuFrame::sampling.x); shaders/lib/sampler.glsl has the dimension table.
#define SAMPLER_SOBOL 0u            // Owen-scrambled Sobol, padded in 2-D pairs (default)
#define SAMPLER_INDEPENDENT 1u      // one PCG32 stream per (pixel, sample)

// Russian roulette (GpuFrame::sampling.z); docs/design.md says how the default was chosen.
#define RR_ORIGINAL 0u              // after 3 bounces, survive with clamp(max(beta), 0.05, 1)
#define RR_MITSUBA 1u               // from depth 5, survive with min(max(beta eta^2), 0.95)
#define RR_PBRT 2u                  // after 1 bounce, when max(beta eta^2) < 1: survive with it
#define RR_OFF 3u                   // never (max depth ends the path)

// Integrator options (GpuFrame::options.x, bits).
#define OPTION_GLASS_SPLIT 1u       // smooth glass: trace the lobe not taken for its emission (path.glsl)

// Environment types (GpuFrame::envInfo.x).
#define ENV_NONE 0u
#define ENV_CONSTANT 1u
#define ENV_SKY 2u
#define ENV_MAP 3u

// Pixel filters (GpuFrame::camInfo.y).
#define FILTER_BOX 0u
#define FILTER_TENT 1u
#define FILTER_GAUSSIAN 2u

// Integrator strategies (GpuFrame::counts.w): MIS is the product; the other two exist so that
// tests can show that all three estimate the same integral.
#define STRATEGY_MIS 0u
#define STRATEGY_LIGHT_ONLY 1u
#define STRATEGY_BSDF_ONLY 2u

// A sphere or a parallelogram.
// sphere: a, b, c = rows of the affine world-to-object matrix (the object is the unit sphere);
// quad:   a.xyz = corner, b.xyz = first edge, c.xyz = second edge; front normal = cross(b, c).
// info: x: PRIM_*, y: material index, z: light index + 1 (0: not a light), w: PRIM_FLAG_*
#define GPU_PRIMITIVE_ROWS(V4, U4, V3U, UUUU) V4(a) V4(b) V4(c) U4(info)
CAUSTIC_STRUCT(GpuPrimitive) { GPU_DECLARE(GPU_PRIMITIVE_ROWS) };

// Which member means what for each model: the header of its file in shaders/bsdf/.
// A node of a BVH (renderer/bvh.h): count = countAndAxis >> 2 (0: interior, left child = next
// node, right child = rightOrFirst), axis = countAndAxis & 3; a leaf's primitives are
// [rightOrFirst, rightOrFirst + count) of its list.
#define GPU_BVH_NODE_ROWS(V4, U4, V3U, UUUU) V3U(boundsMin, rightOrFirst) V3U(boundsMax, countAndAxis)
CAUSTIC_STRUCT(GpuBvhNode) { GPU_DECLARE(GPU_BVH_NODE_ROWS) };

// A node of a mesh's 4-wide BVH (renderer/bvh.h, collapseBvh4 and quantizeWideNode;
// geometry/walk_wide4.glsl reads its texels), 64 bytes, 4 texels: the four children's boxes quantised to bytes on a grid
// per axis (bound = origin + q * 2^(e - 127)): the origin's float bits in head.xyz and the biased
// exponents e in bytes 0-2 of head.w; qXY = (lo x, hi x, lo y, hi y), qZ.xy = (lo z, hi z), child
// k's byte k of each word. The decoded boxes contain the children's (an empty child's is
// inverted: never hit). Children: WIDE_CHILD_EMPTY, a leaf's word (WIDE_CHILD_LEAF | count <<
// LEAF_COUNT_SHIFT | first: triangles [first, first + count) of the mesh's; a longer binary leaf
// becomes a node of leaves), or the index of a child node in wideNodes.
// head: xyz: origin (float bits), w: exponents; qZ.zw: unused.
#define GPU_WIDE_BVH_NODE_ROWS(V4, U4, V3U, UUUU) U4(head) U4(qXY) U4(qZ) U4(child)
CAUSTIC_STRUCT(GpuWideBvhNode) { GPU_DECLARE(GPU_WIDE_BVH_NODE_ROWS) };
#define WIDE_CHILD_EMPTY 0xffffffffu
#define WIDE_CHILD_LEAF LEAF_BIT
#define WIDE_LEAF_MAX_COUNT LEAF_MAX_COUNT
#define WIDE_LEAF_MAX_FIRST LEAF_MAX_FIRST

// A placed mesh: the affine transforms both ways (rows), its trees and triangles.
//   rootNode: its binary BVH's root in bvhNodes; wideRoot: its 4-wide BVH's root in wideNodes;
//   firstTriangle, triangleCount: its triangles in triangles[]; firstVertex: its vertices';
//   material: its material (with fileMaterials = 1: the first of the file's, each triangle's own
//   offset in p0.w); light: its light index + 1 (0: not emissive); flags: PRIM_FLAG_*.
#define GPU_INSTANCE_ROWS(V4, U4, V3U, UUUU)                                                      \
    V4(worldToObject0) V4(worldToObject1) V4(worldToObject2)                                    \
    V4(objectToWorld0) V4(objectToWorld1) V4(objectToWorld2)                                    \
    UUUU(rootNode, firstTriangle, material, light)                                              \
    UUUU(firstVertex, triangleCount, fileMaterials, flags)                                      \
    UUUU(wideRoot, unused0, unused1, unused2)
CAUSTIC_STRUCT(GpuInstance) { GPU_DECLARE(GPU_INSTANCE_ROWS) };

// One triangle in object space; v: its vertices' indices into the vertex buffer (already offset),
// w: the triangle's index in the mesh as imported.
#define GPU_TRIANGLE_ROWS(V4, U4, V3U, UUUU) V4(p0) V4(p1) V4(p2) U4(v)
CAUSTIC_STRUCT(GpuTriangle) { GPU_DECLARE(GPU_TRIANGLE_ROWS) };

// Shading attributes of a mesh vertex (object space). normalU: xyz unit normal, w texture u;
// tangentV: xyz unit tangent (0 when the mesh has none), w texture v.
#define GPU_VERTEX_ROWS(V4, U4, V3U, UUUU) V4(normalU) V4(tangentV)
CAUSTIC_STRUCT(GpuVertex) { GPU_DECLARE(GPU_VERTEX_ROWS) };

//   albedo:   rgb: diffuse albedo (diffuse models) or specular tint (the others)
//   emission: rgb emitted radiance (both faces unless the primitive is PRIM_FLAG_ONE_SIDED_EMITTER),
//             w: the normal map's scale (x and y of its tangent-space normal)
//   params:   x: roughness (GGX alpha, Oren-Nayar sigma or EON r), y: IOR (inside / outside)
//   info:     x: MAT_*, y: MAT_FLAG_*, z: with MAT_FLAG_ALPHA_MASK the alpha cutoff (float bits),
//             w: dielectrics and volumes: the nesting priority (integrator/medium.glsl); surfaces with
//             MAT_FLAG_TRANSMISSION_PART or MAT_FLAG_SUBSURFACE_PART: the index of the first part, and
//             params.z... as surface.glsl says, sheen.w... (integrator/surface_parts.glsl reads them)
//   eta, k:   conductors: rgb real and imaginary (extinction) parts of the complex IOR
//             dielectrics and volumes with MAT_FLAG_MEDIUM: the interior medium's coefficients per
//             scene unit, k.rgb absorption sigma_a, eta.rgb scattering sigma_s, eta.w the
//             Henyey-Greenstein anisotropy g (renderer/gpu_materials.cpp derives them from OpenPBR's
//             transmission_color / transmission_depth / transmission_scatter)
//   textures: texture index + 1 (0: none): x albedo (linear RGB; A: the alpha of the cut-outs),
//             y normal map, z roughness (R), w emission (linear RGB, times emission.rgb)
//   sheen:    surface: rgb sheen colour (times its weight), w sheen roughness
#define GPU_MATERIAL_ROWS(V4, U4, V3U, UUUU) \
    V4(albedo) V4(emission) V4(params) U4(info) V4(eta) V4(k) U4(textures) V4(sheen)
CAUSTIC_STRUCT(GpuMaterial) { GPU_DECLARE(GPU_MATERIAL_ROWS) };
// The rows that traversal's alpha test reads alone (geometry/alpha_mask.glsl); renderer/gpu_scene.cpp
// checks them against the list, so a row inserted before them fails the build.
#define GPU_MATERIAL_ROW_INFO 3u
#define GPU_MATERIAL_ROW_TEXTURES 6u

// A texture in the texel buffer: its mip levels follow each other from `offset`, level l being
// max(1, width >> l) x max(1, height >> l) texels, rows top to bottom.
// info: x: offset of level 0 (in texels), y: width, z: height, w: number of levels (bits 0-7),
// TEXTURE_WRAP_* of u (bits 8-9) and of v (bits 10-11).
#define GPU_TEXTURE_ROWS(V4, U4, V3U, UUUU) U4(info)
CAUSTIC_STRUCT(GpuTexture) { GPU_DECLARE(GPU_TEXTURE_ROWS) };
#define TEXTURE_WRAP_REPEAT 0u      // glTF's REPEAT (and every scene texture)
#define TEXTURE_WRAP_CLAMP 1u       // CLAMP_TO_EDGE
#define TEXTURE_WRAP_MIRROR 2u      // MIRRORED_REPEAT

// mesh:   p0.x = total world area; info.z = instance index, info.w = offset of its triangle CDF
//         (triangle count = the instance's info2.y)
// rect:   p0 = corner, p1.xyz = edge u, p1.w = area, p2.xyz = edge v
// sphere: p0.xyz = centre, p0.w = radius
// point:  p0.xyz = position
// spot:   p0.xyz = position, p1.xyz = unit direction, p1.w = cos(outer), p2.w = cos(inner),
//         p2.x = outer, p2.y = inner (radians)
// env:    nothing (the environment is described by GpuFrame)
// color: rgb: radiance (area, env) or intensity (point, spot); w: selection probability of the
//        global CDF (power or uniform selection)
// info:  x: LIGHT_*, y: flags, z: primitive index (area lights), w: see above (mesh)
// tree:  x: the light's path in the light tree (bit d set: the right child at depth d;
//        renderer/light_tree.h), y, z, w: unused
#define GPU_LIGHT_ROWS(V4, U4, V3U, UUUU) V4(p0) V4(p1) V4(p2) V4(color) U4(info) U4(tree)
CAUSTIC_STRUCT(GpuLight) { GPU_DECLARE(GPU_LIGHT_ROWS) };

// A node of the light tree (Conty Estevez and Kulla 2018, "Importance Sampling of Many Lights
// with Adaptive Tree Splitting"): the bounds of the lights below it, in space (a box) and in
// emitted directions (a cone: every light's normal within theta_o of `axis`, and it emits up to
// theta_e beyond its normal), and their summed intensity (luminance, W sr^-1, the most each light
// sends towards one point; renderer/light_tree.h).
// boundsMin: xyz box, w intensity; boundsMax: xyz box, w cos theta_o; axis: xyz unit cone axis,
// w cos theta_e; info: x: right child (interior: the left child is the next node), or
// LIGHT_TREE_LEAF | light index; y, z, w: unused.
#define GPU_LIGHT_NODE_ROWS(V4, U4, V3U, UUUU) V4(boundsMin) V4(boundsMax) V4(axis) U4(info)
CAUSTIC_STRUCT(GpuLightNode) { GPU_DECLARE(GPU_LIGHT_NODE_ROWS) };

// Per-dispatch constants (std140; only vec4/uvec4 so std140 == std430 == C++).
//   camPosition: the camera's position
//   camRight: unit right * tan(half horizontal fov)
//   camUp: unit up * tan(half vertical fov)
//   camForward: unit view direction
//   image: x: width, y: height, z: index of the first sample of this dispatch, w: seed
//   counts: x: primitives, y: lights, z: max depth, w: STRATEGY_*
//   dispatch: x: samples per dispatch, y: environment light index + 1 (0: none), z, w: the
//     integrator's 8x8 tiles [z, w) this dispatch renders (numbered row by row)
//   envInfo: x: ENV_*, y: map width, z: map height, w: sampling cells per texel and axis
//   envRadiance: constant radiance (already times intensity)
//   envHorizon: sky: radiance at the horizon (times intensity)
//   envZenith: sky: radiance at the zenith (times intensity)
//   envMap: map: x = cos(rotation), y = sin(rotation), z = intensity
//   camLens: x: aperture radius, y: focal distance, z: squeeze, w: blade rotation (rad)
//   camInfo: x: blades (0: round), y: FILTER_*, z: 1 when the camera is a lens system (LensBlock)
//   geometry: x: top-level BVH nodes (0: empty scene), y: instances
//   tables: offsets into the tables buffer (one storage block for all of them: Mesa allows 16
//     per shader): x: light selection CDF, y: environment map row CDF (H + 1), z: environment
//     map per-row column CDFs (H (W + 1)), w: emissive meshes' triangle-area CDFs.
//   sampling: x: SAMPLER_*, y: LIGHT_SELECT_*, z: RR_*, w: light tree nodes (0: none)
//   envSelect: x: the environment's importance for light selection (its irradiance,
//     pi * mean luminance), y: 1 when every light is an environment
//   rayOffset: x: the scale below which ray offsets stop shrinking with the hit's
//     magnitude (geometry/intersect.glsl, offsetRayOrigin); y, z, w: unused
//   options: x: OPTION_* bits (integrator options); y, z: the origin of the crop the
//     accumulation images hold (path.comp); w: the number of point and spot lights (the lights
//     equiangular sampling in media aims at, integrator/medium.glsl)
//   mediumA, mediumS: the scene's medium (the one outside every object, where the camera is):
//     rgb absorption sigma_a and w the Henyey-Greenstein g; rgb scattering sigma_s, w unused
//   aperture: the camera's aperture image in the tables buffer: x: offset of its row CDF (z + 1
//     entries), then its rows' CDFs (z (y + 1)), then its texels (y z, row 0 the top); y, z: its
//     width and height; w: 1 when the camera has one (integrator/camera.glsl)
//   envGuide: the environment map's guide tables in the tables buffer (environment.glsl,
//     envFindInterval): x: offset of the row CDF's (2^z + 1 entries), y: offset
//     of the column CDFs' (one of 2^w + 1 entries per row), z, w: log2 of their
//     bucket counts
#define GPU_FRAME_ROWS(V4, U4, V3U, UUUU) \
    V4(camPosition) V4(camRight) V4(camUp) V4(camForward) U4(image) U4(counts) U4(dispatch) \
    U4(envInfo) V4(envRadiance) V4(envHorizon) V4(envZenith) V4(envMap) V4(camLens) U4(camInfo) \
    U4(geometry) U4(tables) U4(sampling) V4(envSelect) V4(rayOffset) U4(options) U4(envGuide) V4(mediumA) V4(mediumS) U4(aperture)
CAUSTIC_STRUCT(GpuFrame) { GPU_DECLARE(GPU_FRAME_ROWS) };

#ifdef __cplusplus
}  // namespace caustic::gpu
#endif
#endif
