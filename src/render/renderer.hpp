#pragma once
// The one renderer shared by render, compare, bench and the viewer: uploads a Scene, draws it
// with a technique into an offscreen target, and reads colour, depth and counters back.
// Needs a current GL 4.5 context (platform/context.hpp).
#include "common/shared.h"
#include "core/camera.hpp"
#include "core/image.hpp"
#include "gl/objects.hpp"
#include "maps/conemap.hpp"
#include "render/eye_prism.hpp"
#include "render/scene.hpp"
#include "render/technique.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pr {

// Reads an RGBA8 texture's level 0 (bottom row first, as GL stores it).
RgbaImage read_texture_rgba8(GLuint texture, int width, int height);

// The histogram of height samples per fragment: bin n holds the fragments that took n samples
// below kExactSampleBins; past it each octave has 1024 bins (shaders/common/counters.glsl,
// sample_bin), up to 2^31. The fewest samples a fragment in `bin` took.
inline constexpr int kExactSampleBins = 1 << PR_EXACT_SAMPLE_BITS; // (common/shared.h)
inline constexpr int kSampleBinsPerOctave = 1 << PR_OCTAVE_SAMPLE_BITS;
inline std::uint64_t sample_bin_low(std::size_t bin)
{
    if (bin < std::size_t(kExactSampleBins)) return bin;
    const std::size_t octave = (bin - kExactSampleBins) / kSampleBinsPerOctave + PR_EXACT_SAMPLE_BITS,
                      step = (bin - kExactSampleBins) % kSampleBinsPerOctave;
    return std::uint64_t(kSampleBinsPerOctave + step) << (octave - PR_OCTAVE_SAMPLE_BITS);
}

// Per-draw GPU counters (instrumented variants only).
struct SampleCounters {
    std::uint64_t fragments = 0;  // fragments that ran the technique's shader
    std::uint64_t samples = 0;    // height samples taken by marchers (contract definition)
    std::uint64_t prisms = 0;     // prisms the prism walk's view rays crossed (counters.glsl)
    std::uint32_t prisms_most = 0; // the most one fragment's ray crossed
    std::vector<std::uint64_t> histogram; // fragments by samples taken (bins: sample_bin_low)
};

class Renderer {
public:
    Renderer(int width, int height);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }
    void resize(int width, int height);

    // Where derived maps (cone maps) are cached; default default_cache_dir(). Cone maps are built
    // (or read from the cache) on the first draw that needs them, before its timing starts.
    void set_cache_dir(std::filesystem::path dir)
    {
        cache_dir_ = std::move(dir);
        cone_entries_.clear();
    }
    const std::filesystem::path& cache_dir(); // the one set, else default_cache_dir(); empty: none
    // No cache at all (--no-cache): derived maps are built in memory and kept for this run only.
    void disable_cache()
    {
        no_cache_ = true;
        cone_entries_.clear();
    }

    // Called while a draw builds a cone map that is not in the cache (render, compare and bench
    // show a progress bar on a terminal): what is built ("relaxed cone map of builtin:noise@1024")
    // and the fraction done, ending at 1. Cache hits call it with 1 only.
    using ConeProgress = std::function<void(const std::string& what, double fraction)>;
    void set_cone_progress(ConeProgress progress) { cone_progress_ = std::move(progress); }

    // Where a draw builds a missing cone map: the CPU's threads (default), or the compute shader
    // in this renderer's own context (render/conemap_gpu.hpp: the same map, bit for bit), for a
    // real GPU; on llvmpipe the threads are as fast or faster (docs/cone-maps.md).
    void set_cone_maps_on_gpu(bool gpu) { cone_gpu_ = gpu; }
    bool cone_maps_on_gpu() const { return cone_gpu_; }

    // Cone maps built elsewhere (the viewer builds them on a thread while it goes on drawing):
    // what a draw with `map` would have to build or read from the cache first, not in memory (for
    // AuxMap::Relaxed the relaxed map and the cone map both), each once; and the hand-over of one
    // such map, which the draws then use instead of building it (a map for a height field that no
    // object draws with any more is dropped). The viewer reads the cached ones itself
    // (read_cached_cone_map, which never builds) and has the rest built on its thread.
    struct ConeMapNeed {
        std::shared_ptr<const HeightField> field;
        ConeKind kind;
        bool cached = false; // its cache entry exists (it may still be damaged)
    };
    std::vector<ConeMapNeed> missing_cone_maps(AuxMap map);
    void provide_cone_map(const std::shared_ptr<const HeightField>& field, ConeMap map);

    // The prism reads its mesh as buffer textures, of at most GL_MAX_TEXTURE_BUFFER_SIZE texels
    // (2^27 on llvmpipe: the walk's eight texels per prism, a mesh of about 16 million
    // triangles); a larger mesh fails with one clear error. Tests lower the limit (0: OpenGL's
    // own) to reach that error with a small mesh.
    void set_texture_buffer_limit(GLint64 texels) { texture_buffer_limit_ = texels; }

    // How the walk's second pass over tears (docs/prism.md, item 9) finds the pixels the first
    // pass marked. Tiles reads the marked tiles back and draws, under each tile's scissor, the
    // prisms whose bottoms may cover it: llvmpipe runs a fragment's whole shader even where it
    // discards at once. Whole reads nothing back and draws every prism's bottom, each fragment
    // discarding at once where its pixel is not marked: on a GPU the read-back's wait (the second
    // pass starting on an idle GPU) cost a sixth of the rock's frame. The default follows
    // GL_RENDERER: Tiles on llvmpipe and softpipe, Whole elsewhere. Both draw the same image.
    enum class TearPass { Tiles, Whole };
    void set_tear_pass(TearPass pass) { tear_pass_ = pass; }
    TearPass tear_pass() const { return tear_pass_; }

    // Uploads meshes and textures (mip-mapped, repeat wrap; R16 for 16-bit heights). The scene
    // may be dropped afterwards: the renderer keeps copies of what it draws with.
    void upload(const Scene& scene);

    // Throws pr::Error where the uploaded scene cannot be drawn with `settings`: the prism with a
    // shell too large for its single-precision geometry. draw() checks it too; commands that
    // draw several techniques check them all first, before printing or writing anything.
    // `option`: the flag that chose the technique, named by the error ("--techniques" in compare).
    void check_drawable(const DrawSettings& settings, const std::string& option = "--technique") const;

    // Whether the prism draws object `object`'s base mesh instead of its shell: a displacement
    // asked for (reach over 0) under a millionth of the object's size, too thin for the prism's
    // single precision (draw() warns once an upload). render --json says so per object.
    bool prism_shell_too_thin(std::size_t object) const;

    // Clears to transparent and draws every object. Returns the wall time of the draw up to
    // glFinish in milliseconds (contract "ms"). Builds the shader variant on first use.
    double draw(const Camera& camera, glm::vec3 light_dir, const DrawSettings& settings);

    // Tessellates and uploads the `reference` technique's geometry for this camera (the automatic
    // level depends on pixel size). `scene` must be the one given to upload(). Generation is
    // chunked, so CPU memory holds one chunk at a time; the GPU holds the whole result.
    struct ReferenceStats {
        int level = 0;               // the finest object's
        std::vector<int> levels;     // each object's, in the scene's order (one number gave the
                                     // first's: found by an exploratory session, thirty-fifth)
        std::size_t triangles = 0;   // all objects
        std::size_t bytes = 0;       // GPU bytes of vertex and index data
        double build_ms = 0.0;
        bool capped = false;         // an automatic level was lowered to fit max_triangles below
                                     // its texel and pixel criteria (not below the cheap floor
                                     // alone, nor for being out of view)
        std::vector<char> capped_objects; // which objects' were (each object's, in order)
    };
    ReferenceStats prepare_reference(const Scene& scene, const Camera& camera, const ReferenceOptions& options);

    // How fine the reference's last shadow map was against the pixels it shaded: one map (per
    // direction of a soft light) spans every point the image shows, so a far or large object in
    // view stretches it. `coarse_share`: the share of the shown points whose pixel is narrower
    // than half a texel (their shadows lose detail: a bump's shadow goes); `widest`: the widest
    // texel there, in those points' pixels. Zero before any shadowed reference was drawn.
    struct ShadowFit {
        double coarse_share = 0.0;
        double widest = 0.0;
    };
    ShadowFit shadow_fit() const { return shadow_fit_; }

    RgbaImage read_color() const;               // RGBA8, alpha = coverage, bottom row first
    std::vector<float> read_depth() const;      // window depth in [0,1]: 1 at the near plane, 0 = nothing drawn
    SampleCounters read_counters() const;       // after a draw with settings.count_samples
    // Tests: each count (fragments, every bin) starts `below` under 2^32 instead of at 0, so that a
    // small draw carries into the high words (counters.glsl); 0 (the default) starts at 0.
    void start_counts_below_carry(std::uint32_t below) { counts_below_carry_ = below; }

    // Builds (or returns the cached) program for a variant; throws pr::Error with the log.
    // The prism walk has variants by the mesh's UV seams: Seamless for a mesh without any (it
    // samples no height where it crosses from prism to prism), Through for a torn mesh
    // (GpuObject::tears) that goes through the tears, and Inside, the second pass from inside
    // the object (docs/prism.md); Plain for the rest and for the other techniques. UnderSurface:
    // walks that start under the surface: from an eye inside a bump (ShellDraw::FromEye), from
    // the bottoms seen from inside a closed object's body or from below an open mesh
    // (ShellDraw::Bottoms).
    // OpenEntry: the listed prisms of an open mesh, whose walls a ray may enter under the
    // surface, and then walks on under it.
    enum class WalkVariant { Plain, Seamless, Through, Inside, UnderSurface, OpenEntry };
    // How the prism's shell is drawn: Faces, by the geometry shader from each triangle (the exact
    // and per-vertex exits); for the walk, Tops and on open meshes Bottoms (the caps, by the
    // vertex shader alone), and Listed (by the geometry shader from one point per listed prism:
    // the other faces of the prisms whose shell folds, the walls along open edges; in the second
    // pass over a torn mesh, the bottoms over marked tiles), and FromEye (one triangle over the
    // screen whose walks start at the eye, when it is inside the shell: docs/prism.md, item 12).
    enum class ShellDraw { Faces, Tops, Bottoms, Listed, FromEye };
    // `color_texture`: the object drawn has a colour texture (PR_COLOR_TEXTURE). A compile-time
    // choice: llvmpipe runs both arms of every branch whatever the lanes take, and the prism's
    // colour level and fetch, behind a uniform flag, were 11 % of its frame on the blob without
    // a colour texture (docs/benchmarks.md, forty-second session).
    GLuint program_for(const DrawSettings& settings, WalkVariant variant = WalkVariant::Plain,
                       ShellDraw shell = ShellDraw::Faces, bool color_texture = false);

    GLuint framebuffer() const { return fbo_.id(); }

    // Drops every built program, so the next draw rebuilds them from the shader sources (the
    // viewer's hot reload; sources come from PRISMRELIEF_SHADER_DIR when set).
    void reload_shaders()
    {
        programs_.clear();
        shadow_program_ = {};
        shadow_eye_program_ = {};
        shadow_light_.reset(); // (the reference's shadow map is drawn again with the new shaders)
    }

    // Wireframe overlays (viewer, docs figures), drawn over the current target and depth-tested
    // against what is there: the base mesh's edges, or the edges of the prism shells that
    // `settings` would draw. Defined in wireframe.cpp.
    enum class Overlay { BaseMesh, PrismShell };
    void draw_overlay(const Camera& camera, Overlay overlay, glm::vec4 color, const DrawSettings& settings);

private:
    // Triangles in the MeshVertex layout, ready to draw.
    struct Geometry {
        gl::VertexArray vao;
        gl::Buffer vertices;
        gl::Buffer indices;
        GLsizei index_count = 0;
    };
    static Geometry make_geometry(const std::vector<MeshVertex>& vertices,
                                  const std::vector<std::uint32_t>& indices);
    // A vertex array reading MeshVertex attributes from `vertices` and elements from `indices`.
    static gl::VertexArray make_vertex_array(GLuint vertices, GLuint indices);

    struct GpuObject {
        Geometry base;
        // The prism walk's data, built on its first draw (ensure_walk_data), of the walk's
        // triangles: per prism its corners, neighbours (edge_adjacency()) and flags
        // (walk_triangles), whether it has edges without a neighbour, shell corners per vertex;
        // `tears`: closed, with UV seams, where the surface may tear (a second pass,
        // docs/prism.md). `walk`: those triangles when they are not the base mesh's, its flat,
        // evenly mapped stretches merged into fewer, larger prisms (merge_flat_regions,
        // docs/prism.md item 11); its `vertices` stays empty (the base's buffer is read).
        Geometry walk;
        gl::Buffer prisms;
        bool open_shell = false;
        // The most prisms one walk crosses (ObjectBlock::u_walk; walk_prism_limit in
        // renderer.cpp): 256, and twice the most walk triangles around one welded position, up
        // to 4096 of them (a fan of 2000 slivers around a disc's centre took the walk past 256
        // prisms: holes, IoU 0.92), and twice the object's diameter over its narrow triangles'
        // width (slivers along a cylinder).
        int walk_max_prisms = 256;
        std::string name; // what warnings call it (SceneObject::place)
        // Whether the base mesh is closed (every edge paired, consistently wound), for culling
        // a depth-writing base technique's back faces; learnt on first need (closed_shell()).
        std::optional<bool> closed;
        bool tears = false;
        bool seamless = false; // no UV seam at all (WalkVariant::Seamless)
        gl::Buffer corners;
        // The prism's views of its data as buffer textures (shared.h, PR_TEX_VERTICES..CORNERS):
        // vertices and indices on the first prism draw (ensure_prism_data), the walk's with it.
        gl::Texture vertex_texels, index_texels, prism_texels, corner_texels;
        gl::Texture walk_index_texels; // of walk.indices, when the walk has its own
        // Every walk prism's number in order (r32ui), the list TearPass::Whole draws (made on its
        // first need).
        gl::Buffer every_prism;
        gl::Texture every_prism_texels;
        // The prisms whose faces other than the caps the walk draws (walk_triangles: folded ones,
        // bit 31 set, and those with an open edge), with the tight tops and with full ones (r32ui
        // buffer textures, PR_TEX_PRISM_LIST).
        gl::Buffer listed[2];
        gl::Texture listed_texels[2];
        GLsizei listed_count[2] = {0, 0};
        // The walk's triangles and shell corners (as in `corners`) on the CPU: to pick the second
        // pass's prisms of a torn mesh (prisms_over_marked_tiles), and with the boxes of blocks of
        // them to find a prism that holds the eye (find_eye_prism).
        std::vector<std::uint32_t> triangles;
        std::vector<glm::vec4> shell_corners;
        PrismBlocks eye_blocks;
        std::vector<Geometry> reference; // chunks of the tessellated ground truth
        GLuint height_texture = 0; // owned by texture_cache_
        GLuint color_texture = 0;  // 0: plain base colour
        std::shared_ptr<const HeightField> height_field; // for cone maps, built on demand
        float height_low = 0.0f, height_high = 1.0f;      // its lowest and highest texel
        GLuint aux_texture[3] = {0, 0, 0}; // cone, relaxed cone, max pyramid; owned by aux_cache_
        GLuint patch_texture[2] = {0, 0};  // the cone and relaxed maps' patches (make_patch_texture); owned by aux_cache_
        glm::ivec2 height_size{0};
        // Copied from the SceneObject, so the Scene need not outlive the upload.
        float depth = 0.0f;
        float midlevel = 0.0f;
        float shell_radius = 0.0f; // of the sphere around its displacement shell (Scene::object_bounds)
        bool thin_shell_said = false; // the prism's warning that its shell is too thin (draw)
        glm::dvec3 shell_center{0.0}; // world space
        // The object's own frame: world positions less `origin` (its transform's translation,
        // in double), which the shaders and the walk's data work in, with the camera brought to
        // it (upload_object). An object translated by 10^6 had world coordinates whose floats
        // are 0.06 apart, and its prism drew noise (IoU 0.86; 0.976 at 10^5).
        glm::dvec3 origin{0.0};
        glm::mat4 local{1.0f}; // the transform less its translation: object to its own frame
        glm::vec3 base_color{0.8f};
    };
    // program_for() for drawing object `o`: its colour-texture variant follows the object.
    GLuint object_program(const DrawSettings& settings, const GpuObject& o, WalkVariant variant = WalkVariant::Plain,
                          ShellDraw shell = ShellDraw::Faces)
    {
        return program_for(settings, variant, shell, o.color_texture != 0);
    }

    void create_target();

    int width_;
    int height_;
    gl::Framebuffer fbo_;
    gl::Texture color_target_;
    gl::Texture depth_target_;
    gl::Texture tear_mask_;  // r32ui, the walk's pixels that went into an object (made on first need)
    gl::Texture tear_tiles_; // r32ui, the same per tile of PR_TEAR_TILE^2 pixels
    TearPass tear_pass_ = TearPass::Tiles;
    bool software_ = false; // llvmpipe or softpipe: GL buffers live in this process's memory
    gl::Buffer pass_list_;          // the second pass's prisms (r32ui), rewritten per draw
    gl::Texture pass_list_texels_;  // its buffer texture (PR_TEX_PRISM_LIST)
    // The reference's shadow maps (ensure_shadow_map): depth from the light across the points the
    // image shows (one layer along the light for hard shadows; for soft ones, one per direction
    // over its disc), each layer's projection of the world (less its origin) into its clip space,
    // and the light and camera they were drawn for (empty: none yet, or the geometry changed since).
    gl::Texture shadow_map_; // a 2D array of depth32f layers
    gl::Texture shadow_depth_; // a view of it that reads the depths themselves (nearest, no comparison)
    int shadow_map_size_ = 0, shadow_map_layers_ = 0;
    gl::Framebuffer shadow_fbo_;
    gl::Program shadow_program_;     // the map's depth (shadow_map.vert)
    gl::Program shadow_eye_program_; // the camera's depth, for what the image shows (the same, PR_SHADOW_FROM_EYE)
    struct ShadowLayer {
        glm::mat4 view_proj{1.0f};
        glm::dvec3 origin{0.0};
    };
    std::vector<ShadowLayer> shadow_layers_;
    std::uint32_t counts_below_carry_ = 0; // start_counts_below_carry
    ShadowFit shadow_fit_;
    glm::vec2 shadow_bias_{0.0f}; // the look-up's offset off the triangle (world) and depth bias (0..1)
    int shadow_layer_drawn_ = 0;  // the layer ensure_shadow_map draws (u_shadow_bias.w)
    std::optional<glm::vec3> shadow_light_;
    float shadow_light_tan_ = 0.0f; // the soft light's angular radius (tangent) it was drawn for; 0: hard
    Camera shadow_camera_;        // the camera it was drawn for, and the target's aspect (compared
    float shadow_aspect_ = 0.0f;  // field by field, in double: a float view matrix far from the origin missed small moves)
    gl::Buffer frame_ubo_;
    gl::Buffer object_ubo_;
    gl::Buffer counters_;
    std::vector<GpuObject> objects_;
    std::map<std::string, gl::Program> programs_;
    std::map<const void*, gl::Texture> texture_cache_; // heights/colours shared by objects
    std::map<std::pair<const void*, int>, gl::Texture> aux_cache_; // (height field, AuxMap - 1), and
    // (height field, AuxMap - 1 + kPatchTextureKey) for the cone maps' patch textures
    static constexpr int kPatchTextureKey = 8;
    // Cone maps in memory, by height field and kind: built by a draw or handed over; kept across
    // uploads for the height fields still drawn (the viewer's depth slider uploads again).
    struct HeldConeMap {
        std::shared_ptr<const HeightField> field; // keeps the key's address from being reused
        ConeMap map;
    };
    std::map<std::pair<const void*, ConeKind>, HeldConeMap> cone_maps_;
    struct MergedTriangles {
        std::uint64_t key; // Fnv of the vertices and indices
        std::size_t vertex_count, index_count;
        std::vector<std::uint32_t> indices;
    };
    static constexpr std::size_t kMergedKept = 4;
    std::vector<MergedTriangles> merged_; // walk_triangles_of(), most recent first
    // Cache entry paths of the drawn height fields (missing_cone_maps), by field and kind.
    std::map<std::pair<const void*, ConeKind>, std::filesystem::path> cone_entries_;
    ConeProgress cone_progress_;
    bool cone_gpu_ = false;
    // The cone map of `kind` for `field`: from memory, else the cache directory, else built.
    const ConeMap& cone_map(const std::shared_ptr<const HeightField>& field, ConeKind kind);
    std::filesystem::path cache_dir_;
    bool no_cache_ = false;
    GLint64 texture_buffer_limit_ = 0;
    // Builds (or reads from the cache) and uploads the derived map each object needs, and with
    // `patches` the base-surface cone marchers' patch texture of a cone or relaxed map.
    void ensure_aux_textures(AuxMap map, bool patches);
    // Depth as Camera::projection makes it: clip z from 0 to w, nearer is greater (depth test
    // GL_GREATER, cleared to 0). Set before every draw: the viewer's panel shares the context.
    static void use_reversed_depth();
    // Fills and binds the frame block (camera, light, viewport) and binds the object block.
    // `light_size`: the light's angular diameter in degrees (soft shadows, DrawSettings::light_size).
    void upload_frame(const Camera& camera, glm::vec3 light_dir, glm::vec2 pixel_offset = glm::vec2(0.0f),
                      float light_size = kDefaultLightSize);
    // The frame block of upload_frame()'s camera, light and shift with its origin at `origin`
    // (an object's frame, GpuObject::origin): upload_object() calls it for each object.
    void upload_frame_block(const glm::dvec3& origin);
    Camera frame_camera_;
    glm::vec3 frame_light_{0.0f, 1.0f, 0.0f};
    float frame_light_tan_ = 0.0f; // tangent of the light's angular radius
    glm::vec2 frame_offset_{0.0f};
    // Fills the object block for `o` drawn with `settings` (draw() and draw_overlay()).
    // `eye`: the prism that holds the eye, for the walk from the eye (ShellDraw::FromEye).
    void upload_object(const GpuObject& o, const DrawSettings& settings, float midlevel,
                       const EyeInShell* eye = nullptr);
    void ensure_walk_data(); // adjacency, shell corners, open_shell, tears and seamless of every object
    // The object's mesh read back from its own buffers (the walk's data and closed_shell()).
    static void read_back_mesh(const GpuObject& o, std::vector<MeshVertex>& vertices, std::vector<std::uint32_t>& indices);
    // Whether o's mesh is closed: from the walk's data when built, else from its edges alone.
    static bool closed_shell(GpuObject& o);
    // merge_flat_regions() of a mesh, remembered for the last few meshes that merged: it is the
    // slow part of a large flat mesh's walk data (1.4 s for a million triangles), and the viewer
    // uploads the same meshes again whenever the depth or midlevel changes. Keyed by content.
    std::vector<std::uint32_t> walk_triangles_of(const std::vector<MeshVertex>& vertices,
                                                 const std::vector<std::uint32_t>& indices);
    void ensure_prism_data(bool walk); // the buffer textures of every object (and the walk's data)
    // The reference's shadow maps for a light along `light_dir` (unit, towards the light), over
    // what the frame's camera shows: one along it (hard shadows, `soft` false), or one from each
    // of PR_SHADOW_LAYERS directions over its disc of angular radius atan(light_tan). Drawn unless
    // the ones there are for that light, camera and geometry. After upload_frame(); uses the
    // frame's target's depth.
    void ensure_shadow_map(glm::vec3 light_dir, bool soft, float light_tan);
    static constexpr int kShadowMapSize = 4096;     // hard shadows: one map
    static constexpr int kSoftShadowMapSize = 2048; // soft: PR_SHADOW_LAYERS maps (256 MB)
    // To their texture units; with `walk`, the walk's triangles.
    static void bind_prism_data(const GpuObject& o, bool walk);
    static const Geometry& walk_geometry(const GpuObject& o) { return o.walk.vao ? o.walk : o.base; }
};

} // namespace pr
