#include "render/scene.hpp"

#include "core/builtin_maps.hpp"
#include "core/error.hpp"
#include "core/transform.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

namespace pr {

Box shell_box(const SceneObject& obj)
{
    // (Was the base mesh's box grown by the reach on every side: a plane's one-sided shell was
    // framed off centre.) In double, as the camera that frames it: in floats the box of an
    // object 10^7 out was off by a unit.
    const glm::dmat3 normals(normal_matrix(obj.transform));
    Box b;
    for (const MeshVertex& v : obj.mesh.vertices) {
        const glm::dvec3 p = glm::dvec3(obj.transform * glm::dvec4(glm::dvec3(v.position), 1.0));
        const glm::dvec3 n = glm::normalize(normals * glm::dvec3(v.normal));
        for (const double h : {0.0, 1.0}) {
            const glm::dvec3 q = p + double(obj.depth) * (h - double(obj.midlevel)) * n;
            b.lo = glm::min(b.lo, q);
            b.hi = glm::max(b.hi, q);
        }
    }
    return b;
}

Sphere sphere_around(const Box& box)
{
    // The floor was 1e-6 scene units: objects smaller than that (scales down to 1e-15 are
    // allowed) were framed as 1e-6 across, a speck, or nothing. Then a millionth of the centre's
    // largest coordinate, float's rounding there; since the camera and the bounds are double, and
    // each object is drawn in floats relative to its own origin, 1e-15 of it, a few of double's
    // rounding steps (a torus 1.2e7 out was framed as 25 units across, not 3).
    const glm::dvec3 centre = 0.5 * (box.lo + box.hi);
    const double largest = std::max({std::abs(centre.x), std::abs(centre.y), std::abs(centre.z)});
    return {centre, std::max({0.5 * glm::length(box.hi - box.lo), 1e-15 * largest, 1e-30})};
}

namespace {

// A file's identity for reading it once: its path with links and "..", "." resolved as the
// kernel resolves them (a scene's "../m.obj" and "./../m.obj" are one file; its paths are kept as
// written since the thirty-fifth session, and each spelling was read, warned of and uploaded
// again; found by a review). A built-in map, or a path that does not resolve (every part must
// exist, as for the kernel: "nodir/../m.obj" is no file, where weakly_canonical made it m.obj's),
// is its text.
std::string file_identity(const std::string& name)
{
    if (name.empty() || builtin::is_builtin(name)) return name;
    std::error_code ec;
    std::filesystem::path p = std::filesystem::canonical(name, ec);
    return ec ? name : p.string();
}

// Texture coordinates far from 0 for their maps: a float there steps by more than a texel of
// the height or colour map, and the surface comes out as noise (u offset by 1e5 on a 512² map:
// 17 dB against the same mesh at 0; found by an exploratory session, thirty-fifth). Up to 2^20
// they are taken (past it refused, mesh_prepare); said, with what to do.
// Each axis against its maps' texels along it: u against their widths, v their heights (a v of 3000
// over a 16384 x 2 colour map warned of 16384-texel maps, whose 2 rows it steps over finely;
// found by an exploratory session, fifty-third).
void warn_if_uv_too_coarse(const SceneObject& obj, const std::string& mesh)
{
    float largest = 0.0f;
    double step = 0.0;
    int texels = 1;
    for (int axis = 0; axis < 2; ++axis) {
        const auto along = [axis](int width, int height) { return axis == 0 ? width : height; };
        int n = obj.height ? along(obj.height->width, obj.height->height) : 1;
        if (obj.color) n = std::max(n, along(obj.color->width, obj.color->height));
        const float at = obj.mesh.largest_uv_axes[axis];
        if (!(at > 0.0f)) continue;
        const double s = double(std::nextafter(at, INFINITY)) - double(at); // a float's step there
        if (s <= 1.0 / double(n) || s * n <= step * texels) continue;
        largest = at;
        step = s;
        texels = n;
    }
    if (step == 0.0) return;
    char text[160];
    std::snprintf(text, sizeof text, "texture coordinates reach %.6g, where single precision steps by %.3g of a "
                                     "repeat, more than a texel of its %d-texel maps",
                  double(largest), step, texels);
    warn(mesh + ": " + text + ": the surface comes out as noise" +
         (obj.mesh.largest_uv_generated ? " (use a smaller --uv-scale)"
                                        : " (they repeat: take whole numbers off them in the file)"));
}

} // namespace

Scene load_scene(const SceneSpec& spec)
{
    if (spec.objects.empty()) throw Error("--mesh", "no mesh given");
    Scene scene;
    std::map<std::string, PreparedMesh> meshes;  // read, and named again by a later object (file_identity)
    std::map<std::string, std::size_t> uses;     // objects still to come that name each file
    for (const ObjectSpec& o : spec.objects) ++uses[file_identity(o.mesh)];
    std::map<std::string, std::shared_ptr<const HeightField>> heights;
    std::map<std::string, std::shared_ptr<const RgbaImage>> colors;
    Box all;
    // A loader's error under the place the scene file gave the value, if it did.
    const auto placed = [](const std::string& place, auto&& load) {
        try {
            return load();
        } catch (const Error& e) {
            if (place.empty()) throw;
            throw e.under(place);
        }
    };
    std::size_t triangles = 0; // the objects' so far, together
    for (const ObjectSpec& o : spec.objects) {
        SceneObject obj;
        obj.mesh_name = o.mesh;
        obj.place = o.mesh_place.empty() ? o.mesh : o.mesh_place;
        // Each file read and prepared once (a scene of 60 objects of one 1M-triangle mesh read it
        // 60 times: over two minutes; found by an exploratory session); each object its copy,
        // the last one naming it the mesh itself (one object: no copy at all).
        const std::string mesh_file = file_identity(o.mesh);
        auto found = meshes.find(mesh_file);
        if (found == meshes.end())
            found = meshes.emplace(mesh_file, placed(o.mesh_place, [&] { return load_mesh(o.mesh, spec.mesh_options); })).first;
        // --max-triangles bounds the scene's objects together too: each object is drawn (and
        // kept) on its own, so a small scene naming one mesh 100,000 times ran out of memory
        // after half a minute, said as "render: out of memory" (found by an exploratory session,
        // forty-ninth).
        triangles += found->second.triangle_count();
        if (triangles > spec.mesh_options.max_triangles)
            throw Error(obj.place,
                        "the scene's objects up to this one hold " + std::to_string(triangles) +
                            " triangles together, more than --max-triangles " +
                            std::to_string(spec.mesh_options.max_triangles) +
                            " (each object counts its mesh's triangles, also where objects share a file)");
        if (--uses[mesh_file] == 0) {
            obj.mesh = std::move(found->second);
            meshes.erase(found);
        } else {
            obj.mesh = found->second;
        }
        auto& h = heights[file_identity(o.height)];
        if (!h)
            h = placed(o.height_place,
                       [&] { return std::make_shared<HeightField>(load_height(o.height, spec.image_limits)); });
        obj.height = h;
        obj.height_name = o.height;
        if (!o.color.empty()) {
            auto& c = colors[file_identity(o.color)];
            if (!c)
                c = placed(o.color_place,
                           [&] { return std::make_shared<RgbaImage>(load_color(o.color, spec.image_limits)); });
            obj.color = c;
            obj.color_name = o.color;
        }
        const std::string& mesh_place = obj.place;
        warn_if_uv_too_coarse(obj, mesh_place);
        // (A mesh far from its file's origin is kept relative to PreparedMesh::origin.) Positions
        // past kMaxCoordinate are refused as a scene's translations are.
        obj.transform = o.transform * glm::translate(glm::dmat4(1.0), obj.mesh.origin);
        obj.placement = o.transform;
        // A mirroring transform (negative determinant) turns the triangles' winding: counter-
        // clockwise seen from outside in the mesh becomes clockwise in world space, where faces
        // are judged (culling, gl_FrontFacing, the prism's faces and walk). Each triangle reversed
        // keeps world space counter-clockwise seen from outside (PreparedMesh::indices).
        if (glm::determinant(glm::dmat3(o.transform)) < 0.0)
            for (std::size_t t = 0; t + 2 < obj.mesh.indices.size(); t += 3)
                std::swap(obj.mesh.indices[t + 1], obj.mesh.indices[t + 2]);
        // (Under a shear or an unequal scale: the mesh's normals and frames as placed, as the file
        // with the transform baked into it gives them; a sheared cube lost a face's triangle.)
        place_mesh_frames(obj.mesh, glm::dmat3(obj.transform));
        obj.midlevel = o.midlevel;
        obj.base_color = o.base_color;

        // World-space bounds of the base mesh: its box's corners transformed where the transform
        // keeps boxes boxes (scales, translations, quarter turns, mirrors); else the box of its
        // transformed vertices. (The rotated box's corners alone made a box too large: the torus
        // turned 45° in a scene got a default depth 40 % deeper than the same turn in its file,
        // which the docs promise draws the same; found by an exploratory session.)
        glm::dvec3 olo(INFINITY), ohi(-INFINITY);
        const glm::dmat3 linear(obj.transform);
        bool keeps_boxes = true;
        for (int row = 0; row < 3; ++row)
            keeps_boxes = keeps_boxes && (linear[0][row] != 0.0) + (linear[1][row] != 0.0) + (linear[2][row] != 0.0) <= 1;
        const auto grow = [&](glm::dvec3 p) {
            const glm::dvec3 w = glm::dvec3(obj.transform * glm::dvec4(p, 1.0));
            olo = glm::min(olo, w);
            ohi = glm::max(ohi, w);
        };
        if (keeps_boxes)
            for (int i = 0; i < 8; ++i)
                grow(glm::dvec3((i & 1) ? obj.mesh.bbox_max.x : obj.mesh.bbox_min.x,
                                (i & 2) ? obj.mesh.bbox_max.y : obj.mesh.bbox_min.y,
                                (i & 4) ? obj.mesh.bbox_max.z : obj.mesh.bbox_min.z));
        else
            for (const MeshVertex& v : obj.mesh.vertices) grow(glm::dvec3(v.position));
        const double diagonal = glm::length(ohi - olo);
        obj.depth = o.depth.value_or(float(0.04 * diagonal));
        const std::string depth_place = o.depth_place.empty() ? (o.depth ? "--depth" : o.mesh) : o.depth_place;
        if (!std::isfinite(obj.depth) || obj.depth < 0.0f)
            throw Error(depth_place, o.depth ? "must be a finite number >= 0"
                                             : "the default depth (4% of the bounding box's diagonal) is not a finite number");
        // Sizes single precision draws, each object in its own frame: the shaders square lengths
        // and multiply them, which overflow past about 1e19 and flush to zero under about 1e-22.
        // Beyond these every technique drew nothing, exit 0, with a warning to check the camera:
        // a depth of 1e22 on the torus (the prism alone refused it, blaming --technique), a
        // triangle 1e19 or 1e-23 units across in the file (found by exploratory sessions).
        constexpr double kLargestAcross = 1e18, kSmallestAcross = 1e-21;
        const auto across_text = [](double across) {
            char text[32];
            std::snprintf(text, sizeof text, "%.3g", across);
            return std::string(text);
        };
        if (!(diagonal <= kLargestAcross) || !(diagonal >= kSmallestAcross))
            throw Error(mesh_place, "the object is " + across_text(diagonal) + " scene units across (its box's diagonal), " +
                                        (diagonal >= kSmallestAcross ? "more than the renderer's single precision draws (1e18): scale it down"
                                                                     : "less than the renderer's single precision draws (1e-21): scale it up") +
                                        " (a scene's transform \"scale\", or the file's units)");
        // Where its box's centre lands (the file's origin is the centre only for a mesh that was
        // kept relative to it: one centred at 3e15 but large for it was let through; found by an
        // exploratory session, thirty-fifth). After the size check, which says more of a mesh
        // both huge and far.
        const glm::dvec3 at = 0.5 * (olo + ohi);
        const double far = std::max({std::abs(at.x), std::abs(at.y), std::abs(at.z)});
        if (far > kMaxCoordinate) {
            char where[96];
            std::snprintf(where, sizeof where, "%.6g, %.6g, %.6g", at.x, at.y, at.z);
            throw Error(mesh_place, std::string("the object lies more than 1e15 scene units from the origin (its centre at ") +
                                        where + "), past the renderer's precision: move it nearer");
        }
        // Small for its place: the camera that frames it is placed in double, whose steps there
        // are a fair part of the object, and the sphere that frames it is at least a few steps
        // wide (sphere_around) (a torus 3.6e-10 across at x = 3e5, where doubles are 5.8e-11
        // apart, drew at half its size, at 1e6 not at all, with no word but "nothing was drawn";
        // found by an exploratory session, forty-fourth). It must span 16 of them, which a 3-unit
        // object at 9e14, 24 steps across, does (it moves by a few pixels: docs/scenes.md).
        // (ilogb of 0 is no number to shift by: an object centred on the origin has no such limit.)
        if (far > 0.0) {
            const double step = std::ldexp(1.0, std::ilogb(far) - 52);
            if (diagonal < 16.0 * step) {
                char what[256];
                std::snprintf(what, sizeof what,
                              "the object is %.3g scene units across at %.3g from the origin, where doubles are "
                              "%.2g apart, too small to place there (16 of those steps at least): move it nearer "
                              "the origin or scale it up",
                              diagonal, far, step);
                throw Error(mesh_place, what);
            }
        }
        const Box box = shell_box(obj);
        if (const Sphere s = sphere_around(box); !(2.0 * s.radius <= kLargestAcross))
            throw Error(depth_place, "the object's displacement shell is too large for the renderer's single "
                                     "precision (" + across_text(2.0 * s.radius) + " scene units across, at most 1e18): use a smaller depth");
        all.lo = glm::min(all.lo, box.lo);
        all.hi = glm::max(all.hi, box.hi);
        scene.object_bounds.push_back(sphere_around(box));
        scene.objects.push_back(std::move(obj));
    }
    // One field for maps of the same texels under other names (builtin:noise and builtin:noise@512,
    // an image and its copy), as for one file under one name above: the renderer keeps a field's
    // cone maps, textures and pyramids by the field, and built or uploaded each twice (found by an
    // exploratory session, thirty-seventh). Each object keeps its own name for the reports.
    std::vector<std::shared_ptr<const HeightField>> distinct;
    for (SceneObject& obj : scene.objects) {
        const auto same = std::find_if(distinct.begin(), distinct.end(), [&](const auto& d) {
            return d == obj.height || (d->width == obj.height->width && d->height == obj.height->height &&
                                       d->bits == obj.height->bits && d->texels == obj.height->texels);
        });
        if (same == distinct.end())
            distinct.push_back(obj.height);
        else
            obj.height = *same;
    }
    scene.shell_bounds = sphere_around(all);
    return scene;
}

void fit_scene_clip_planes(Camera& camera, const Scene& scene, double grow)
{
    std::vector<Sphere> objects = scene.object_bounds;
    double most = 0.0;
    for (std::size_t k = 0; k < objects.size(); ++k) {
        const double reach = grow + (k < scene.objects.size() ? kCarveReach * double(scene.objects[k].depth) : 0.0);
        objects[k].radius += reach;
        most = std::max(most, reach);
    }
    Sphere all = scene.shell_bounds;
    all.radius += most;
    fit_clip_planes(camera, objects, all);
}

Camera scene_camera(const SceneSpec& spec, const Scene& scene)
{
    const CameraSpec& c = spec.camera;
    const float aspect = static_cast<float>(spec.width) / static_cast<float>(spec.height);
    Camera camera;
    if (c.eye) {
        camera.eye = *c.eye;
        camera.target = c.target.value_or(scene.shell_bounds.center);
        camera.up = c.up;
        camera.fovy_deg = c.fovy_deg;
        // (The options check a camera whose target is given, naming the flag or the scene key;
        // without one the target is the shell's centre, known only now.)
        // An eye from a scene file: the file's keys can mend it too.
        const bool flag_eye = c.eye_place.rfind("--", 0) == 0;
        switch (view_problem(glm::dvec3(camera.eye), glm::dvec3(camera.target), glm::dvec3(camera.up))) {
        case ViewProblem::SamePoint: // (no target was given: it said "eye and target are the same point")
            throw Error(c.eye_place, std::string("is the shell's centre, the default target (give ") +
                                         (flag_eye ? "--target)" : "camera.target, or --target)"));
        case ViewProblem::UpAlongView: {
            // (A file's up and the flag's eye: the flag is said, or the file's up alone read as the
            // fault; thirty-sixth session.)
            if (c.up_given)
                throw Error(c.up_place, "up is parallel to the viewing direction" +
                                            (flag_eye && c.up_place.rfind("--", 0) != 0
                                                 ? " from " + c.eye_place + " to the shell's centre (give --up or --target)"
                                                 : std::string()));
            throw Error(c.eye_place, std::string("looks straight along the default up direction 0,1,0 at the shell's "
                                                 "centre (give ") +
                                         (flag_eye ? "--up or --target)" : "camera.up or camera.target, or --up or --target)"));
        }
        case ViewProblem::None: break;
        }
        fit_scene_clip_planes(camera, scene);
        return camera;
    }
    Sphere s = scene.shell_bounds;
    if (c.target) {
        s.radius = glm::length(s.center - *c.target) + s.radius;
        s.center = *c.target;
    }
    camera = frame_sphere(s, c.fovy_deg, aspect, c.elevation_deg, c.azimuth_deg, c.up);
    fit_scene_clip_planes(camera, scene);
    return camera;
}

glm::vec3 scene_light(const SceneSpec& spec, const Camera& camera)
{
    if (spec.light) return glm::normalize(*spec.light);
    const glm::mat3 to_world = glm::transpose(glm::mat3(camera.view()));
    return glm::normalize(to_world * glm::vec3(-0.4f, 0.75f, 0.55f));
}

} // namespace pr
