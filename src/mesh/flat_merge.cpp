// Merging flat, evenly textured stretches of a mesh for the prism walk (flat_merge.hpp): vertices
// whose removal changes nothing are taken out by halfedge collapses in OpenMesh, in rounds, until
// none is left.
#include "mesh/flat_merge.hpp"

#include "mesh/quiet_openmesh.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace pr {
namespace {

using glm::dvec2;
using glm::dvec3;
using std::size_t;
using std::uint32_t;
using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

// Relative tolerance of "the same" plane, mapping and frame: float input computed in double. A
// region of n texels merged with it moves the mapping by about n * 1e-5 texels.
constexpr double kSame = 1e-5;
// The smallest sine of a corner angle a merged triangle may have (in space and in uv).
constexpr double kMinSine = 1e-6;
// The longest edge in texture space (UV units) a merged triangle may have: twice the texture's
// side, which a segment of its prism is sampled along in full (prism.frag, segment_ray()).
constexpr double kMaxMergedUv = 2.0;
// Vertices with more edges wait for their neighbours to go first (Merger::run).
constexpr std::size_t kMaxValence = 10;

bool near(const dvec3& a, const dvec3& b, double scale) { return glm::length(a - b) <= kSame * scale; }

double cross2(const dvec2& a, const dvec2& b) { return a.x * b.y - a.y * b.x; }

// A triangle's texture mapping: P = P_a + dpdu (u - u_a) + dpdv (v - v_a) over its plane.
struct Mapping {
    dvec3 dpdu{0.0}, dpdv{0.0};
    bool valid = false;
};

Mapping mapping_of(const MeshVertex& a, const MeshVertex& b, const MeshVertex& c)
{
    const dvec3 e1 = dvec3(b.position) - dvec3(a.position), e2 = dvec3(c.position) - dvec3(a.position);
    const dvec2 t1 = dvec2(b.uv) - dvec2(a.uv), t2 = dvec2(c.uv) - dvec2(a.uv);
    const double det = cross2(t1, t2);
    Mapping m;
    if (!(std::abs(det) > kMinSine * glm::length(t1) * glm::length(t2))) return m; // degenerate in uv
    if (!(glm::length(glm::cross(e1, e2)) > kMinSine * glm::length(e1) * glm::length(e2))) return m;
    m.dpdu = (e1 * t2.y - e2 * t1.y) / det;
    m.dpdv = (e2 * t1.x - e1 * t2.x) / det;
    m.valid = std::isfinite(m.dpdu.x + m.dpdu.y + m.dpdu.z + m.dpdv.x + m.dpdv.y + m.dpdv.z);
    return m;
}

bool same_mapping(const Mapping& a, const Mapping& b)
{
    const double scale = glm::length(a.dpdu) + glm::length(a.dpdv);
    return a.valid && b.valid && near(a.dpdu, b.dpdu, scale) && near(a.dpdv, b.dpdv, scale);
}

// What the shell and the hit's frame interpolate besides P and uv.
bool same_frame(const MeshVertex& a, const MeshVertex& b)
{
    const double scale = glm::length(dvec3(a.tangent)) + glm::length(dvec3(a.bitangent));
    return near(dvec3(a.normal), dvec3(b.normal), 1.0) && a.tangent.w == b.tangent.w &&
           near(dvec3(a.tangent), dvec3(b.tangent), scale) && near(dvec3(a.bitangent), dvec3(b.bitangent), scale);
}

class Merger {
public:
    // `render_of`: the render vertex of each of the mesh's vertices.
    Merger(const std::vector<MeshVertex>& vertices, const std::vector<uint32_t>& render_of, Mesh& mesh,
           const std::vector<uint32_t>& copies)
        : v_(vertices), render_of_(render_of), m_(mesh), copies_(copies), removable_(mesh.n_vertices(), -1)
    {
    }

    // Rounds of collapses until no vertex can go; the number of collapses. In each round every
    // vertex that may go and has at most kMaxValence edges goes along its shortest edge that
    // keeps the shape and whose other end has not taken a collapse in this round (so no vertex
    // gathers edges faster than they go: a planar mesh always has many vertices of low valence,
    // and each round removes about half of them); when none of those is left, the rest (beside
    // vertices that stay, a vertex may keep many edges). Vertex by vertex without rounds piled
    // the removed vertices' edges onto a few, and every check walks a vertex's ring: 4.4 s on a
    // 400 x 400 quad floor; a global queue by edge length 1.6 s; rounds 0.4 s.
    std::size_t run()
    {
        std::size_t collapses = 0;
        std::vector<std::uint32_t> round_of(m_.n_vertices(), 0);
        std::vector<std::pair<double, Mesh::HalfedgeHandle>> out;
        std::size_t max_valence = kMaxValence; // lifted once nothing below it can go
        for (std::uint32_t round = 1;; ++round) {
            std::size_t in_round = 0;
            for (int i = 0, n = int(m_.n_vertices()); i < n; ++i) {
                const Mesh::VertexHandle v0(i);
                if (m_.status(v0).deleted() || round_of[size_t(i)] == round || !may_go(v0)) continue;
                out.clear();
                std::size_t valence = 0;
                for (const Mesh::HalfedgeHandle h : m_.voh_range(v0)) {
                    const Mesh::VertexHandle to = m_.to_vertex_handle(h);
                    ++valence;
                    if (round_of[size_t(to.idx())] != round) out.emplace_back(glm::length(pos(to) - pos(v0)), h);
                }
                // Judged again on its ring as it is now: each collapse keeps the merged
                // triangles' corners within kSame of the vertex that goes, so the error cannot
                // creep along chains of vertices each close to the next (a surface curving more
                // gently than kSame per edge stays curved). No vertex that could not go ever can.
                if (valence > max_valence || !removable(v0)) continue;
                std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
                for (const auto& [length, h] : out) {
                    if (!keeps_shape(h) || !m_.is_collapse_ok(h)) continue;
                    round_of[size_t(m_.to_vertex_handle(h).idx())] = round;
                    m_.collapse(h);
                    ++in_round;
                    break;
                }
            }
            if (in_round == 0 && max_valence == SIZE_MAX) return collapses;
            if (in_round == 0) max_valence = SIZE_MAX; // hubs beside vertices that stay
            collapses += in_round;
        }
    }

private:
    const MeshVertex& vertex(Mesh::VertexHandle v) const { return v_[render_of_[size_t(v.idx())]]; }
    dvec3 pos(Mesh::VertexHandle v) const { return dvec3(vertex(v).position); }
    dvec2 uv(Mesh::VertexHandle v) const { return dvec2(vertex(v).uv); }

    // A face's corners in order, starting at `first`.
    std::array<Mesh::VertexHandle, 3> corners_from(Mesh::FaceHandle f, Mesh::VertexHandle first) const
    {
        std::array<Mesh::VertexHandle, 3> c;
        int k = 0;
        for (const Mesh::VertexHandle v : m_.fv_range(f)) c[size_t(k++)] = v;
        while (c[0] != first) std::rotate(c.begin(), c.begin() + 1, c.end());
        return c;
    }

    // The only copy of its position, its faces one plane with one mapping, its neighbours its frame.
    bool removable(Mesh::VertexHandle v0) const
    {
        const MeshVertex& a = vertex(v0);
        if (copies_[a.weld_id] != 1) return false;
        Mapping first;
        for (const Mesh::FaceHandle f : m_.vf_range(v0)) {
            const auto c = corners_from(f, v0);
            const Mapping m = mapping_of(a, vertex(c[1]), vertex(c[2]));
            if (!first.valid) {
                if (!m.valid) return false;
                first = m;
            } else if (!same_mapping(first, m)) {
                return false;
            }
        }
        if (!first.valid) return false; // an isolated vertex
        for (const Mesh::VertexHandle w : m_.vv_range(v0))
            if (!same_frame(a, vertex(w))) return false;
        return true;
    }

    // Moving v0 onto v1 leaves the same region covered, every face turned as before and none
    // degenerate; on a boundary, v0 must lie on a straight run of it between v1 and the other
    // boundary neighbour.
    bool keeps_shape(Mesh::HalfedgeHandle h) const
    {
        const Mesh::VertexHandle v0 = m_.from_vertex_handle(h), v1 = m_.to_vertex_handle(h);
        if (m_.is_boundary(v0)) {
            // Where pieces meet at a single vertex (a bowtie; the ends of a T-junction's long
            // edge), the vertex has several boundary gaps and the one its halfedge names can pair
            // a boundary edge of one piece with a collinear one of the other: moving it would
            // change the region covered (holes in the prism's walk, IoU 0.60 on a bowtie).
            if (!m_.is_manifold(v0)) return false;
            if (!m_.is_boundary(m_.edge_handle(h))) return false;
            const Mesh::HalfedgeHandle out = m_.halfedge_handle(v0); // OpenMesh keeps it on the boundary
            if (!m_.is_boundary(out)) return false;
            const Mesh::VertexHandle ahead = m_.to_vertex_handle(out);
            const Mesh::VertexHandle behind = m_.from_vertex_handle(m_.prev_halfedge_handle(out));
            const Mesh::VertexHandle v2 = ahead == v1 ? behind : ahead;
            const dvec3 d1 = pos(v1) - pos(v0), d2 = pos(v2) - pos(v0);
            if (!(glm::dot(d1, d2) < 0.0)) return false;
            if (!(glm::length(glm::cross(d1, d2)) <= kSame * glm::length(d1) * glm::length(d2))) return false;
        }
        for (const Mesh::FaceHandle f : m_.vf_range(v0)) {
            const auto c = corners_from(f, v0);
            if (c[1] == v1 || c[2] == v1) continue; // collapses with the edge
            const dvec3 pa = pos(c[1]), pb = pos(c[2]);
            const dvec3 before = glm::cross(pa - pos(v0), pb - pos(v0));
            const dvec3 e1 = pa - pos(v1), e2 = pb - pos(v1), e3 = pb - pa;
            const dvec3 after = glm::cross(e1, e2);
            if (!(glm::dot(before, after) > 0.0)) return false;
            const double longest = std::max({glm::length(e1), glm::length(e2), glm::length(e3)});
            if (!(glm::length(after) > kMinSine * longest * longest)) return false;
            const dvec2 ua = uv(c[1]), ub = uv(c[2]);
            const double uv_before = cross2(ua - uv(v0), ub - uv(v0));
            const dvec2 t1 = ua - uv(v1), t2 = ub - uv(v1), t3 = ub - ua;
            const double uv_after = cross2(t1, t2);
            const double uv_longest = std::max({glm::length(t1), glm::length(t2), glm::length(t3)});
            if (!(uv_before * uv_after > 0.0)) return false;
            if (!(std::abs(uv_after) > kMinSine * uv_longest * uv_longest)) return false;
            // No merged triangle across more than two repeats of the texture, unless its face was
            // already: the walk's march takes a sample per two texels along a prism's segment up
            // to four lengths of the height map (prism.frag, segment_ray()), and a floor tiled
            // 10 times merged into two triangles left thin walls between samples.
            const double uv_longest_before =
                std::max({glm::length(ua - uv(v0)), glm::length(ub - uv(v0)), glm::length(t3)});
            if (uv_longest > std::max(kMaxMergedUv, uv_longest_before)) return false;
        }
        return true;
    }

    // Whether v may go at all, as first judged. A vertex that could not go never can (a
    // neighbour with another frame or a face with another mapping cannot go either), so a "no"
    // is kept; run() judges a "yes" again on the ring as it is before each collapse.
    bool may_go(Mesh::VertexHandle v)
    {
        signed char& r = removable_[size_t(v.idx())];
        if (r < 0) r = removable(v) ? 1 : 0;
        return r == 1;
    }

    const std::vector<MeshVertex>& v_;
    const std::vector<uint32_t>& render_of_;
    Mesh& m_;
    const std::vector<uint32_t>& copies_;
    std::vector<signed char> removable_; // per vertex: -1 not judged yet, 0 no, 1 yes
};

// Copies per welded position (a vertex on a UV seam has two or more).
std::vector<uint32_t> copies_per_position(const std::vector<MeshVertex>& vertices)
{
    std::vector<uint32_t> copies;
    for (const MeshVertex& v : vertices) {
        if (v.weld_id >= copies.size()) copies.resize(size_t(v.weld_id) + 1, 0);
        ++copies[v.weld_id];
    }
    return copies;
}

// A first look without OpenMesh, per vertex: 1 where its faces and neighbours would let it go
// (the merge checks again on the mesh as it changes), 2 where not, 0 for unused vertices.
std::vector<uint8_t> candidates(const std::vector<MeshVertex>& vertices, const std::vector<uint32_t>& indices,
                                const std::vector<uint32_t>& copies)
{
    const size_t faces = indices.size() / 3;
    std::vector<Mapping> mapping(faces);
    for (size_t f = 0; f < faces; ++f)
        mapping[f] = mapping_of(vertices[indices[3 * f]], vertices[indices[3 * f + 1]], vertices[indices[3 * f + 2]]);
    std::vector<uint8_t> state(vertices.size(), 0);
    std::vector<uint32_t> face_of(vertices.size(), 0);
    for (size_t f = 0; f < faces; ++f) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = indices[3 * f + size_t(k)];
            if (state[i] == 2) continue;
            bool ok = mapping[f].valid && copies[vertices[i].weld_id] == 1;
            if (ok && state[i] == 1) ok = same_mapping(mapping[face_of[i]], mapping[f]);
            for (int j = 1; ok && j < 3; ++j) ok = same_frame(vertices[i], vertices[indices[3 * f + size_t((k + j) % 3)]]);
            state[i] = ok ? 1 : 2;
            face_of[i] = uint32_t(f);
        }
    }
    return state;
}

bool any_candidate(const std::vector<uint8_t>& state)
{
    return std::any_of(state.begin(), state.end(), [](uint8_t s) { return s == 1; });
}

} // namespace

bool has_flat_stretch(const std::vector<MeshVertex>& vertices, const std::vector<uint32_t>& indices)
{
    return indices.size() >= 6 && any_candidate(candidates(vertices, indices, copies_per_position(vertices)));
}

std::vector<uint32_t> merge_flat_regions(const std::vector<MeshVertex>& vertices, const std::vector<uint32_t>& indices)
{
    const size_t faces = indices.size() / 3;
    if (faces < 2) return indices;
    const std::vector<uint32_t> copies = copies_per_position(vertices);
    const std::vector<uint8_t> state = candidates(vertices, indices, copies);
    if (!any_candidate(state)) return indices; // curved meshes (most) stop here

    // OpenMesh gets only the region that may change: the faces around a candidate or around a
    // neighbour of one. So every edge between two vertices around a candidate is there, and
    // OpenMesh's checks of a collapse see the whole of both ends' rings (also after earlier
    // collapses: a vertex around a merged stretch was around one of its candidates). The rest of
    // a large mesh with a few flat spots is copied as it is.
    std::vector<uint8_t> near(vertices.size(), 0);
    for (size_t f = 0; f < faces; ++f) {
        const uint32_t* t = &indices[3 * f];
        if (state[t[0]] == 1 || state[t[1]] == 1 || state[t[2]] == 1) near[t[0]] = near[t[1]] = near[t[2]] = 1;
    }
    std::vector<uint32_t> kept, region_faces;
    std::vector<int> om_of(vertices.size(), -1);
    std::vector<uint32_t> render_of;
    for (size_t f = 0; f < faces; ++f) {
        const uint32_t* t = &indices[3 * f];
        if (!near[t[0]] && !near[t[1]] && !near[t[2]]) {
            kept.insert(kept.end(), t, t + 3);
            continue;
        }
        region_faces.push_back(uint32_t(f));
        for (int k = 0; k < 3; ++k)
            if (om_of[t[k]] < 0) {
                om_of[t[k]] = int(render_of.size());
                render_of.push_back(t[k]);
            }
    }

    Mesh mesh;
    mesh.request_vertex_status();
    mesh.request_edge_status();
    mesh.request_halfedge_status();
    mesh.request_face_status();
    {
        QuietOpenMesh quiet; // add_face complains on non-manifold input, which comes back unchanged
        for (const uint32_t r : render_of) {
            const glm::vec3& p = vertices[r].position;
            mesh.add_vertex(Mesh::Point(p.x, p.y, p.z));
        }
        for (const uint32_t f : region_faces) {
            const uint32_t* t = &indices[3 * size_t(f)];
            const Mesh::FaceHandle fh = mesh.add_face(Mesh::VertexHandle(om_of[t[0]]), Mesh::VertexHandle(om_of[t[1]]),
                                                      Mesh::VertexHandle(om_of[t[2]]));
            if (!fh.is_valid()) return indices;
        }
    }
    if (Merger(vertices, render_of, mesh, copies).run() == 0) return indices;

    std::vector<uint32_t> merged = std::move(kept);
    for (const Mesh::FaceHandle f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        for (const Mesh::VertexHandle v : mesh.fv_range(f)) merged.push_back(render_of[size_t(v.idx())]);
    }
    return merged;
}

} // namespace pr
