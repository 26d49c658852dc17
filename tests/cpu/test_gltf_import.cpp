// glTF 2.0 import of the files tests/gltf/make_test_gltf.py writes (tests/data/gltf/quad.gltf with
// data-URI PNGs and its .glb twin with the PNGs in buffer views): what was written comes back:
// the factors and extension values, the samplers' wrap modes, the alpha mode, the embedded images
// decoded from memory texel for texel, the KHR_texture_transform applied to the UVs, and one report
// per file for what is not mapped. The script is also run here, and its output must be the
// committed files, so the files and the script cannot drift apart.
#include "renderer/gpu_scene.h"
#include "renderer/mesh_import.h"
#include "renderer/mesh_import_gltf.h"

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>

using namespace caustic;
namespace fs = std::filesystem;

namespace {

const fs::path kData = fs::path(CAUSTIC_SOURCE_DIR) / "tests" / "data" / "gltf";

std::string bytesOf(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

std::string joined(const std::vector<std::string>& lines) {
    std::string all;
    for (const std::string& l : lines) all += l + "\n";
    return all;
}

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST_CASE("the glTF test files are the generator script's output", "[cpu][mesh][gltf]") {
    const fs::path out = fs::temp_directory_path() / ("caustic-gltf-gen-" + std::to_string(::getpid()));
    const std::string command = "python3 \"" + (fs::path(CAUSTIC_SOURCE_DIR) / "tests/gltf/make_test_gltf.py").string() +
                                "\" \"" + out.string() + "\"";
    REQUIRE(std::system(command.c_str()) == 0);
    for (const char* name : {"quad.gltf", "quad.glb", "leaf.gltf", "leaf.glb", "glow.gltf", "glow.glb"}) {
        INFO(name);
        CHECK(bytesOf(out / name) == bytesOf(kData / name));
    }
    fs::remove_all(out);
}

TEST_CASE("glTF import: .gltf (data URIs) and .glb give what the file says", "[cpu][mesh][gltf]") {
    for (const char* name : {"quad.gltf", "quad.glb"}) {
        INFO(name);
        const std::string path = (kData / name).string();
        const MeshImportResult r = importMeshFile(path);
        REQUIRE(r.ok());
        const std::string warnings = joined(r.warnings);
        INFO(warnings);
        REQUIRE(r.materials.size() >= 1);
        const ImportedMaterial& m = r.materials[0];
        CHECK(m.name == "layered");
        CHECK(m.ior == Approx(1.4f));
        CHECK(m.specular == Approx(0.8f));
        CHECK(m.specularColor == glm::vec3(1.0f, 0.9f, 0.8f));
        CHECK(m.clearcoat == Approx(0.5f));
        CHECK(m.clearcoatRoughness == Approx(0.2f));
        CHECK(m.sheenColor == glm::vec3(0.3f, 0.2f, 0.1f));
        CHECK(m.sheenRoughness == Approx(0.6f));
        CHECK(m.emission.x == Approx(0.4f));  // emissiveFactor x KHR_materials_emissive_strength 4
        CHECK(m.emission.y == Approx(0.8f));
        CHECK(m.emission.z == Approx(1.2f));
        CHECK(m.normalScale == Approx(0.5f));
        CHECK(m.alphaMode == 1);
        CHECK(m.alphaCutoff == Approx(0.3f));
        CHECK(m.doubleSided);
        CHECK(m.metallic == 1.0f);
        CHECK(m.roughness == 1.0f);
        CHECK(m.textureWrap(TextureSlot::BaseColor, 0) == kWrapClamp);
        CHECK(m.textureWrap(TextureSlot::BaseColor, 1) == kWrapMirror);
        CHECK(m.textureWrap(TextureSlot::MetallicRoughness, 0) == kWrapRepeat);
        // The embedded images, decoded from memory: the checker's texels are the script's.
        REQUIRE(m.baseColorTexture.size() > 1);
        REQUIRE(m.baseColorTexture[0] == '*');
        const FileTextures files{path, &r.embedded, m.wrap};
        ImageData base, mr;
        std::string error;
        REQUIRE(readTextureImage(ImageReader{}, &files, m.baseColorTexture, &base, &error));
        REQUIRE(base.width == 4);
        REQUIRE(base.height == 4);
        REQUIRE(base.channels == 3);
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                const bool red = (x + y) % 2 == 0;
                const float* px = &base.pixels[size_t(3 * (y * 4 + x))];
                CHECK(px[0] == Approx((red ? 230 : 20) / 255.0));
                CHECK(px[2] == Approx((red ? 30 : 220) / 255.0));
            }
        REQUIRE(readTextureImage(ImageReader{}, &files, m.metallicRoughnessTexture, &mr, &error));
        REQUIRE(mr.width == 2);
        CHECK(mr.pixels[1] == Approx(51 / 255.0));   // left texel: roughness 0.2 (G)
        CHECK(mr.pixels[2] == Approx(1.0));          // metal (B)
        CHECK(mr.pixels[4] == Approx(204 / 255.0));  // right: roughness 0.8, not metal
        CHECK(mr.pixels[5] == Approx(0.0));
        // KHR_texture_transform on the UVs (glTF's v runs down; caustic's up): corner (0, 0) of
        // glTF's UV space goes to the offset, the others by scale then rotation.
        REQUIRE(r.meshes.size() == 1);
        const Mesh& mesh = r.meshes[0];
        REQUIRE(mesh.uvs.size() == 4);
        GltfTextureRef t;
        t.offset = {0.25f, 0.5f};
        t.scale = {2.0f, 0.5f};
        t.rotation = 0.3f;
        const glm::vec2 gltfUv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};  // the script's UVS, per corner
        const glm::vec3 corner[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
        for (size_t v = 0; v < 4; ++v) {
            int k = 0;
            while (k < 4 && glm::length(mesh.positions[v] - corner[k]) > 1e-5f) ++k;
            REQUIRE(k < 4);
            const float c = std::cos(0.3f), s = std::sin(0.3f);
            const glm::vec2 p = gltfUv[k] * glm::vec2(2.0f, 0.5f);
            const glm::vec2 expected = glm::vec2(c * p.x - s * p.y + 0.25f, s * p.x + c * p.y + 0.5f);
            CHECK(mesh.uvs[v].x == Approx(expected.x).margin(1e-5));
            CHECK(mesh.uvs[v].y == Approx(1.0f - expected.y).margin(1e-5));
        }
        // Reports: once per file each.
        CHECK(count(warnings, "KHR_materials_iridescence") == 1);
        CHECK(count(warnings, "alphaMode") == 0);  // MASK is rendered as written: no report
        CHECK(warnings.find("embedded textures are not") == std::string::npos);

        // Mapped onto the layered surface.
        std::vector<std::string> unmapped;
        const Material s = mapImportedMaterial(m, &unmapped);
        CHECK(s.type == MaterialType::Surface);
        CHECK(s.specularIor == Approx(1.4f));
        CHECK(s.coatWeight == Approx(0.5f));
        CHECK(s.sheenWeight == 1.0f);
        CHECK(s.roughnessTexture == m.metallicRoughnessTexture);
    }
}

TEST_CASE("broken embedded images and broken glTF JSON are reported by name, not crashed on", "[cpu][mesh][gltf]") {
    ImageData out;
    std::string error;
    std::string png = bytesOf(kData / "quad.glb");  // not an image
    CHECK_FALSE(decodeImageBytes(png, "model.glb (embedded image 0)", &out, &error));
    CHECK(error.find("model.glb (embedded image 0)") != std::string::npos);
    // A PNG signature over garbage, and a JPEG start marker over garbage.
    CHECK_FALSE(decodeImageBytes(std::string("\x89PNG\r\n\x1a\n", 8) + std::string(64, 'x'), "a.glb (embedded image 1)", &out,
                                 &error));
    CHECK(error.find("not a readable PNG") != std::string::npos);
    CHECK_FALSE(decodeImageBytes(std::string("\xFF\xD8\xFF\xE0", 4) + std::string(64, '\x01'), "a.glb (embedded image 2)",
                                 &out, &error));
    CHECK(error.find("not a readable JPEG") != std::string::npos);
    // An index past the file's images.
    const std::vector<EmbeddedImage> none;
    const FileTextures files{"m.glb", &none, 0};
    CHECK_FALSE(readTextureImage(ImageReader{}, &files, "*7", &out, &error));
    CHECK(error.find("m.glb (embedded image 7)") != std::string::npos);
    // glTF JSON that does not parse, and a truncated GLB chunk.
    const fs::path dir = fs::temp_directory_path() / ("caustic-gltf-bad-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "bad.gltf") << "{\"materials\": [";
    std::string glb = bytesOf(kData / "quad.glb");
    glb.resize(40);
    std::ofstream(dir / "cut.glb", std::ios::binary) << glb;
    for (const char* name : {"bad.gltf", "cut.glb"}) {
        const std::string file = (dir / name).string();
        const GltfForAssimp g = prepareGltfForAssimp(file);
        CHECK(g.error.rfind(file + ": ", 0) == 0);
        const MeshImportResult r = importMeshFile(file);   // refused before Assimp, with the same message
        CHECK(r.error == g.error);
    }
    fs::remove_all(dir);
}

TEST_CASE("glTF alpha MASK and emissive textures import, map and compile as the file says", "[cpu][mesh][gltf]") {
    for (const char* name : {"leaf.gltf", "leaf.glb"}) {
        INFO(name);
        const std::string path = (kData / name).string();
        const MeshImportResult r = importMeshFile(path);
        REQUIRE(r.ok());
        INFO(joined(r.warnings));
        CHECK(joined(r.warnings).find("alphaMode") == std::string::npos);  // MASK is not an approximation
        REQUIRE(r.materials.size() >= 1);
        const ImportedMaterial& m = r.materials[0];
        CHECK(m.alphaMode == 1);
        CHECK(m.alphaCutoff == Approx(0.4f));
        CHECK(m.opacity == Approx(0.8f));
        // The RGBA texture keeps its alpha: 1 in columns 0, 1, 4, 5, 0 in the others.
        const FileTextures files{path, &r.embedded, m.wrap};
        ImageData base;
        std::string error;
        REQUIRE(readTextureImage(ImageReader{}, &files, m.baseColorTexture, &base, &error));
        REQUIRE(base.channels == 4);
        for (int x = 0; x < 8; ++x) CHECK(base.pixels[size_t(4 * x + 3)] == (x % 4 < 2 ? 1.0f : 0.0f));
        // Mapped: a mask whose cutoff has the factor's alpha folded in (alpha x 0.8 < 0.4).
        std::vector<std::string> unmapped;
        const Material s = mapImportedMaterial(m, &unmapped);
        CHECK(s.alphaMode == AlphaMode::Mask);
        CHECK(s.alphaCutoff == Approx(0.5f));
        CHECK(unmapped.empty());
        // Compiled: the flag, the cutoff's bits, the albedo texture in RGBA, and the instance flag.
        Scene scene;
        Object o;
        o.shape = Shape::Mesh;
        o.file = path;
        scene.objects.push_back(o);
        CompiledScene c;
        REQUIRE(compileScene(scene, ImageReader{}, &c, &error));
        REQUIRE(c.materials.size() >= 1);
        CHECK((c.materials[0].info.y & MAT_FLAG_ALPHA_MASK) != 0u);
        CHECK(std::bit_cast<float>(c.materials[0].info.z) == 0.5f);
        CHECK(c.materials[0].textures.x != 0u);
        REQUIRE(c.instances.size() == 1);
        CHECK((c.instances[0].flags & PRIM_FLAG_ALPHA_MASK) != 0u);
    }
    for (const char* name : {"glow.gltf", "glow.glb"}) {
        INFO(name);
        const std::string path = (kData / name).string();
        const MeshImportResult r = importMeshFile(path);
        REQUIRE(r.ok());
        REQUIRE(r.materials.size() >= 1);
        const ImportedMaterial& m = r.materials[0];
        CHECK(m.emission == glm::vec3(3.0f, 1.5f, 0.75f));  // emissiveFactor x emissive strength 3
        REQUIRE(m.emissionTexture.size() > 1);
        CHECK(m.emissionTexture[0] == '*');
        CHECK(m.textureWrap(TextureSlot::Emission, 0) == kWrapClamp);
        std::vector<std::string> unmapped;
        const Material s = mapImportedMaterial(m, &unmapped);
        CHECK(s.emissionTexture == m.emissionTexture);
        CHECK(s.emission == m.emission);
        CHECK(unmapped.empty());
        Scene scene;
        Object o;
        o.shape = Shape::Mesh;
        o.file = path;
        scene.objects.push_back(o);
        CompiledScene c;
        std::string error;
        REQUIRE(compileScene(scene, ImageReader{}, &c, &error));
        REQUIRE(c.materials.size() >= 1);
        REQUIRE(c.materials[0].textures.w != 0u);
        const gpu::GpuTexture& t = c.textures[c.materials[0].textures.w - 1];
        CHECK(t.info.y == 2u);
        CHECK(((t.info.w >> 8) & 3u) == TEXTURE_WRAP_CLAMP);
        REQUIRE(c.lights.size() == 1);
        CHECK(c.lights[0].info.x == LIGHT_MESH);
        CHECK((c.lights[0].info.y & LIGHT_FLAG_EMISSION_TEXTURE) != 0u);
        CHECK((c.instances[0].flags & PRIM_FLAG_ALPHA_MASK) == 0u);
        // Light selection weighs the light by the texture's mean: the two texels' linear RGB
        // averaged, times the factor, over the quad's area 4, both faces (a file's materials).
        auto lin = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
        const glm::dvec3 mean(0.5, 0.5 * (lin(128.0 / 255.0) + lin(64.0 / 255.0)), 0.5);
        const glm::dvec3 radiance = glm::dvec3(3.0, 1.5, 0.75) * mean;
        const double y = 0.2126 * radiance.r + 0.7152 * radiance.g + 0.0722 * radiance.b;
        REQUIRE(c.lightPower.size() == 1);
        CHECK(c.lightPower[0] == Approx(2.0 * 3.14159265358979 * 4.0 * y).epsilon(2e-3));
    }
}

TEST_CASE("glTF alpha BLEND is a mask reported once per file, and a mask on an analytic shape is reported",
          "[cpu][mesh][gltf]") {
    const fs::path dir = fs::temp_directory_path() / ("caustic-gltf-blend-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::string text = bytesOf(kData / "leaf.gltf");
    const size_t at = text.find("\"MASK\"");
    REQUIRE(at != std::string::npos);
    text.replace(at, 6, "\"BLEND\"");
    std::ofstream(dir / "blend.gltf") << text;
    const MeshImportResult r = importMeshFile((dir / "blend.gltf").string());
    REQUIRE(r.ok());
    const std::string warnings = joined(r.warnings);
    INFO(warnings);
    CHECK(count(warnings, "alphaMode BLEND is rendered as MASK") == 1);
    CHECK(warnings.find("blend.gltf") != std::string::npos);
    REQUIRE(r.materials.size() >= 1);
    CHECK(r.materials[0].alphaMode == 2);
    CHECK(r.materials[0].alphaCutoff == 0.5f);  // the file's alphaCutoff 0.4 is MASK's alone
    std::vector<std::string> unmapped;
    const Material s = mapImportedMaterial(r.materials[0], &unmapped);
    CHECK(s.alphaMode == AlphaMode::Mask);
    CHECK(s.alphaCutoff == Approx(0.625f));  // 0.5 / the factor's alpha 0.8
    fs::remove_all(dir);

    Scene scene;
    Material m;
    m.name = "cut";
    m.alphaMode = AlphaMode::Mask;
    scene.materials.push_back(m);
    Object quad;
    quad.shape = Shape::Quad;
    quad.material = "cut";
    scene.objects.push_back(quad);
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(scene, ImageReader{}, &c, &error));
    CHECK(count(joined(c.warnings), "objects[0]: material 'cut' has alpha_mode 'mask', which only meshes honour") == 1);
}

TEST_CASE("a missing emission texture is reported with its material, its key and its file", "[cpu][gltf]") {
    Scene scene;
    Material m{"sign", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(2.0f)};
    m.emissionTexture = "no-such-sign.png";
    scene.materials.push_back(m);
    Object quad;
    quad.shape = Shape::Quad;
    quad.material = "sign";
    scene.objects.push_back(quad);
    const ImageReader missing = [](const std::string& path, ImageData*, std::string* error) {
        *error = path + ": cannot open";
        return false;
    };
    CompiledScene c;
    std::string error;
    CHECK_FALSE(compileScene(scene, missing, &c, &error));
    INFO(error);
    CHECK(error.find("materials[0].emission_texture (material 'sign')") != std::string::npos);
    CHECK(error.find("no-such-sign.png: cannot open") != std::string::npos);
}

TEST_CASE("picking through alpha cut-outs: the CPU query sees the holes the renderer shows", "[gltf][alpha]") {
    // The leaf of the GPU test "alpha cut-outs: camera rays pass where ...": a quad x, y in [-1, 1]
    // at z = 0 whose mask keeps glTF u = (x + 1) / 2 where u mod 1/4 < 1/8. Behind it at z = -1 the
    // same mesh with an opaque material. Rays along -z through the kept stripes hit the leaf
    // (t 4); through the holes they go on to the backing (t 5), never to nothing.
    const fs::path data = fs::path(CAUSTIC_SOURCE_DIR) / "tests" / "data" / "gltf";
    Scene s;
    Object leaf;
    leaf.shape = Shape::Mesh;
    leaf.file = (data / "leaf.glb").string();
    s.objects.push_back(leaf);
    s.materials.push_back({"black", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)});
    Object back = leaf;
    back.material = "black";
    back.transform.translate = glm::vec3(0.0f, 0.0f, -1.0f);
    s.objects.push_back(back);
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, ImageReader{}, &c, &error));
    INFO(error);
    REQUIRE(c.instances.size() == 2);
    int kept = 0, cut = 0;
    for (int i = 0; i < 256; ++i) {
        const float x = -1.0f + (float(i) + 0.5f) / 128.0f;   // centres of 256 columns of width 1/128
        const float u = (x + 1.0f) / 2.0f;
        const bool expectKept = std::fmod(u, 0.25f) < 0.125f;
        const RayHit h = intersectVisibleMeshes(c, Ray{glm::vec3(x, 0.3f, 4.0f), glm::vec3(0.0f, 0.0f, -1.0f)});
        INFO("x " << x);
        REQUIRE(h.hit());
        CHECK(c.instanceObject[h.instance] == (expectKept ? 0u : 1u));
        CHECK(h.t == Approx(expectKept ? 4.0 : 5.0));
        (expectKept ? kept : cut)++;
        // Without the filter every ray stops at the leaf.
        CHECK(c.instanceObject[intersectScene(c.meshBvh, c.meshPositions, Ray{glm::vec3(x, 0.3f, 4.0f), glm::vec3(0.0f, 0.0f, -1.0f)}).instance] == 0u);
    }
    CHECK(kept == 128);
    CHECK(cut == 128);
}
