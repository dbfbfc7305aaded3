#pragma once
// SceneSpec: what the user asked for (plain data, filled from flags or --scene JSON).
// Scene: the loaded CPU data (prepared meshes, height fields, colours) ready to upload.
#include "core/camera.hpp"
#include "core/image.hpp"
#include "mesh/mesh.hpp"

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pr {

struct ObjectSpec {
    std::string mesh;                    // file path
    std::string height = "builtin:bumps"; // file or builtin:NAME
    std::string color;                   // file, builtin:NAME, or empty (uniform base colour)
    std::optional<float> depth;          // scene units; default: 4% of the object's bbox diagonal
    float midlevel = 0.0f;               // height that stays on the base surface (0: outward)
    // Object to world, in double: a translation of 12345678.9 kept to its last digit (a float
    // put the object 0.1 off, and the camera, which is double, saw it there).
    glm::dmat4 transform{1.0};
    glm::vec3 base_color{0.80f, 0.76f, 0.70f};
    // Where a scene file gave the mesh, height and colour ("s.json: objects[1].height"; empty for
    // flags), named by load_scene's errors: "builtin:nope" alone did not say which object's.
    std::string mesh_place, height_place, color_place;
    // Where the depth came from: "--depth", "s.json: objects[0].depth", or empty (the default).
    std::string depth_place;
};

struct CameraSpec {
    std::optional<glm::dvec3> eye;    // with target: explicit camera
    std::optional<glm::dvec3> target; // alone: auto-framed distance around this point
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    bool up_given = false;           // by --up or the scene file (else the default: messages say so)
    // Where the eye and up came from, for scene_camera's messages: the flags, or a scene file's
    // camera ("FILE: camera", "FILE: camera.up").
    std::string eye_place = "--eye";
    std::string up_place = "--up";
    float fovy_deg = 40.0f;
    float elevation_deg = 25.0f; // auto-framing (no --eye)
    float azimuth_deg = 35.0f;
};

struct SceneSpec {
    std::vector<ObjectSpec> objects;
    CameraSpec camera;
    std::optional<glm::vec3> light; // world direction towards the light; default: camera-relative
    int width = 800;
    int height = 600;
    MeshOptions mesh_options;
    ImageLimits image_limits;
};

struct SceneObject {
    std::string mesh_name;
    // What messages call the object: its place in the scene file ("s.json: objects[1].mesh"), or
    // its mesh where it has none (--mesh). (Warnings named the mesh alone, which a scene may name
    // for several objects; found by an exploratory session, fifty-third.)
    std::string place;
    PreparedMesh mesh;
    std::shared_ptr<const HeightField> height; // shared by the objects that name one file
    std::string height_name;                   // the map's file or builtin name as this object gives it
    std::shared_ptr<const RgbaImage> color;    // may be null
    std::string color_name;                    // its file or builtin name, where there is one
    float depth = 0.0f;
    float midlevel = 0.0f;
    // Object to world: the scene's transform (`placement`, ObjectSpec::transform, as the reports
    // give it) after the mesh's own origin (PreparedMesh::origin, an internal change of frame).
    glm::dmat4 transform{1.0};
    glm::dmat4 placement{1.0};
    glm::vec3 base_color{0.8f};
};

struct Scene {
    std::vector<SceneObject> objects;
    Sphere shell_bounds; // world space, encloses every object's full displacement shell
    std::vector<Sphere> object_bounds; // the same per object (clip planes: fit_clip_planes)
};

// The world box of an object's full displacement shell: every vertex moved to both ends of its
// displacement range, depth * (h - midlevel) for h in [0, 1], along its world normal (the prisms
// and the displaced surface lie in the hull of those points).
struct Box {
    glm::dvec3 lo{INFINITY};
    glm::dvec3 hi{-INFINITY};
};
Box shell_box(const SceneObject& obj);
// The sphere around a box, its radius kept above what floats can still tell apart at its centre.
Sphere sphere_around(const Box& box);

// The clip planes around a scene (fit_clip_planes): each object's shell sphere grown by
// kCarveReach times its depth, and by `grow` (the viewer's sliders). The base-surface techniques
// carve inward, up to `depth` under a face wherever the shell runs (it runs outward at the
// default --midlevel 0), and with --depth-write they write the depth of the point they show:
// on a ray at angle a to the face, up to depth / sin(a) past the polygon. kCarveReach = 8 keeps
// rays 7 degrees from the face and steeper inside the far plane; a flatter one's depth is held
// at the far plane (docs/techniques.md, "Depth write"). Until the forty-fourth session the
// planes enclosed the shell alone, and a carved floor beyond it was held at the far plane:
// `compare` under-reported those techniques' depth error (found by an exploratory session).
inline constexpr double kCarveReach = 8.0;
void fit_scene_clip_planes(Camera& camera, const Scene& scene, double grow = 0.0);

// Loads every mesh and image (each distinct file once). Throws pr::Error naming the file.
Scene load_scene(const SceneSpec& spec);

// The camera the spec asks for, or auto-framing on the shell's bounding sphere; near/far from it.
Camera scene_camera(const SceneSpec& spec, const Scene& scene);

// Unit direction towards the light, world space. Default: from above-left-behind the viewer
// (camera space (-0.4, 0.75, 0.55)), so auto-framed views are lit from the front.
glm::vec3 scene_light(const SceneSpec& spec, const Camera& camera);

} // namespace pr
