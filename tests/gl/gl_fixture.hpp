#pragma once
// Shared set-up for GL tests: one OSMesa context per test process, small hand-made scenes.
#include "core/camera.hpp"
#include "core/image.hpp"
#include "mesh/mesh.hpp"
#include "platform/context.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>

namespace prtest {

inline pr::Context& context()
{
    static std::unique_ptr<pr::Context> ctx = pr::create_headless_context(pr::Backend::OSMesa);
    return *ctx;
}

// A height field from a function of (u, v) in [0,1)^2, sampled at texel centres.
template <typename F>
std::shared_ptr<pr::HeightField> height_from(int n, F f)
{
    auto hf = std::make_shared<pr::HeightField>();
    hf->width = hf->height = n;
    hf->name = "test";
    hf->texels.resize(std::size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) hf->texels[std::size_t(y) * n + x] = f((x + 0.5f) / n, (y + 0.5f) / n);
    return hf;
}

// The square [-s, s]^2 in the z = 0 plane facing +Z, UV 0..uv_repeat, metric tangent frame.
inline pr::PreparedMesh square(float s = 1.0f, float uv_repeat = 1.0f)
{
    pr::PreparedMesh m;
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int i = 0; i < 4; ++i) {
        pr::MeshVertex v;
        v.position = glm::vec3(corners[i] * s, 0.0f);
        v.normal = {0, 0, 1};
        v.uv = (corners[i] * 0.5f + 0.5f) * uv_repeat;
        v.tangent = glm::vec4(2.0f * s / uv_repeat, 0, 0, 1);
        v.bitangent = glm::vec3(0, 2.0f * s / uv_repeat, 0);
        v.weld_id = static_cast<std::uint32_t>(i);
        m.vertices.push_back(v);
    }
    m.indices = {0, 1, 2, 0, 2, 3};
    m.weld_count = 4;
    m.bbox_min = {-s, -s, 0};
    m.bbox_max = {s, s, 0};
    m.had_uvs = true;
    return m;
}

inline pr::Scene one_object(pr::PreparedMesh mesh, std::shared_ptr<pr::HeightField> height, float depth)
{
    pr::Scene scene;
    pr::SceneObject o;
    o.mesh_name = "test";
    o.mesh = std::move(mesh);
    o.height = std::move(height);
    o.depth = depth;
    scene.objects.push_back(std::move(o));
    const auto& m = scene.objects[0].mesh;
    scene.shell_bounds.center = 0.5f * (m.bbox_min + m.bbox_max);
    scene.shell_bounds.radius = 0.5f * glm::length(m.bbox_max - m.bbox_min) + depth;
    return scene;
}

// A bundled mesh (meshes/`name`) under `height`, shell `depth` deep.
inline pr::Scene bundled(const std::string& name, std::shared_ptr<pr::HeightField> height, float depth)
{
    return one_object(pr::load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/" + name), std::move(height), depth);
}

// A bundled mesh (meshes/`name`) as a scene's object, the other keys at their defaults.
inline pr::ObjectSpec bundled_object(const std::string& name)
{
    pr::ObjectSpec o;
    o.mesh = std::string(PR_SOURCE_DIR) + "/meshes/" + name;
    return o;
}

// `spec` loaded and framed as the command line loads and frames it (auto-framing unless the
// spec's camera says otherwise).
struct FramedObject {
    pr::Scene scene;
    pr::Camera camera;
};
inline FramedObject framed(const pr::SceneSpec& spec)
{
    FramedObject f{pr::load_scene(spec), {}};
    f.camera = pr::scene_camera(spec, f.scene);
    return f;
}

// meshes/`name` loaded and framed as `render --mesh meshes/NAME --size WIDTHxHEIGHT --elevation
// E [--azimuth A]` does, the other keys at their defaults.
inline FramedObject framed_bundled(const std::string& name, int width, int height, float elevation_deg,
                                   float azimuth_deg = pr::CameraSpec{}.azimuth_deg)
{
    pr::SceneSpec spec;
    spec.objects.push_back(bundled_object(name));
    spec.width = width;
    spec.height = height;
    spec.camera.elevation_deg = elevation_deg;
    spec.camera.azimuth_deg = azimuth_deg;
    return framed(spec);
}

// An OBJ file's text loaded as a mesh (written to a temporary file of this process, then removed).
inline pr::PreparedMesh mesh_from_obj_text(const std::string& obj, const std::string& name)
{
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("prismrelief-test-" + name + "-" + std::to_string(::getpid()) + ".obj");
    {
        std::ofstream out(path);
        out << obj;
    }
    pr::PreparedMesh m = pr::load_mesh(path.string());
    std::filesystem::remove(path);
    return m;
}

// Cone maps built by GL tests are cached here (never in the user's cache).
inline std::filesystem::path cache_dir()
{
    return std::filesystem::temp_directory_path() / "prismrelief-gl-tests-cache";
}

// `scene` uploaded to `r` (GL tests' cache), and a camera framing it from `elevation_deg`,
// `azimuth_deg` (40 degrees, the renderer's aspect).
inline pr::Camera upload_framed(pr::Renderer& r, const pr::Scene& scene, float elevation_deg, float azimuth_deg)
{
    r.set_cache_dir(cache_dir());
    r.upload(scene);
    return pr::frame_sphere(scene.shell_bounds, 40.0f, float(r.width()) / float(r.height()), elevation_deg, azimuth_deg);
}

// `s` drawn from `c` under `light`, and the image read back.
inline pr::RgbaImage drawn(pr::Renderer& r, const pr::Camera& c, glm::vec3 light, const pr::DrawSettings& s)
{
    r.draw(c, light, s);
    return r.read_color();
}

inline std::size_t coverage(const pr::RgbaImage& img)
{
    std::size_t n = 0;
    for (std::size_t i = 3; i < img.pixels.size(); i += 4) n += img.pixels[i] >= 128;
    return n;
}

} // namespace prtest
