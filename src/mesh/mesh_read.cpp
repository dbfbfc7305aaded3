// Reading mesh files through OpenMesh into a RawMesh.
//
// OpenMesh's readers are lenient (contract, "Facts of this platform"): they return success after
// skipping vertices whose numbers do not parse, drop faces with bad indices, loop over header
// counts without checking the end of the file, and allocate for whatever a header claims. So each
// file is validated here first (header counts against the file size, numbers, indices), and
// OpenMesh then reads into our own importer (SoupImporter), which records a plain polygon soup:
// no halfedge topology means no faces rejected as non-manifold and no vertices duplicated.
// OpenMesh parses the very bytes that were validated, from memory: it never opens the user's file
// (which may be a pipe, read once, or change between two reads) nor, for OBJ, a material file.
#include "mesh/quiet_openmesh.hpp"
#include "mesh/raw_mesh.hpp"

#include "core/error.hpp"
#include "core/file_kind.hpp"
#include "core/input_file.hpp"

#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/reader/OBJReader.hh>
#include <OpenMesh/Core/IO/reader/OFFReader.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>
#include <OpenMesh/Core/IO/reader/STLReader.hh>

#include <glm/common.hpp>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <limits>
#include <mutex>
#include <new>
#include <optional>
#include <streambuf>
#include <string_view>

#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace pr {
namespace {

namespace fs = std::filesystem;
namespace omio = OpenMesh::IO;

using std::size_t;
using std::string;
using std::string_view;

[[noreturn]] void fail(const string& subject, const string& problem)
{
    throw Error(subject, problem);
}

string line_prefix(size_t line)
{
    return "line " + std::to_string(line) + ": ";
}

// ---- text scanning -------------------------------------------------------------------------

bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

// Splits a line into at most `max` whitespace-separated tokens; returns how many were found
// (possibly more than `max`, which are counted but not stored).
size_t tokenize(string_view line, string_view* out, size_t max)
{
    size_t n = 0;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        if (i == line.size()) break;
        const size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (n < max) out[n] = line.substr(start, i - start);
        ++n;
    }
    return n;
}

// Iterates the lines of a text, numbering them from 1.
class LineReader {
public:
    explicit LineReader(string_view text, size_t offset = 0, size_t first_line = 1)
        : text_(text), pos_(offset), line_(first_line - 1)
    {
    }
    bool next(string_view& line)
    {
        if (pos_ >= text_.size()) return false;
        const size_t end = text_.find('\n', pos_);
        const size_t stop = end == string_view::npos ? text_.size() : end;
        line = text_.substr(pos_, stop - pos_);
        pos_ = stop + 1;
        ++line_;
        return true;
    }
    size_t line() const { return line_; }
    size_t offset() const { return std::min(pos_, text_.size()); }

private:
    string_view text_;
    size_t pos_;
    size_t line_;
};

// A number token as OpenMesh's stream extraction reads it into a float: must be a whole token
// and finite in single precision (an overflowing "1e39" is not; underflow to 0 is fine). Not
// hexadecimal: strtod takes "0x1p0" for 1, the stream reads 0 and stops at the x (an apex read
// as 0 drew a flat tetrahedron, exit 0). Any length: a 64-byte buffer refused a valid
// "1.000…" of 70 characters.
// `value`, where given, gets the number in double (Expect::positions).
bool parse_finite_float(string_view token, double* value = nullptr)
{
    if (token.empty() || token.find_first_of("xX") != string_view::npos) return false;
    const std::string text(token);
    char* end = nullptr;
    const double d = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size()) return false;
    if (value) *value = d;
    return std::isfinite(d) && std::fabs(d) <= double(FLT_MAX);
}

bool parse_int(string_view token, long long& value)
{
    if (token.empty() || token.size() > 18) return false;
    size_t i = 0;
    bool negative = false;
    if (token[0] == '-' || token[0] == '+') {
        negative = token[0] == '-';
        i = 1;
    }
    if (i == token.size()) return false;
    long long v = 0;
    for (; i < token.size(); ++i) {
        if (token[i] < '0' || token[i] > '9') return false;
        v = v * 10 + (token[i] - '0');
    }
    value = negative ? -v : v;
    return true;
}

string shown(string_view s)
{
    string out(s.substr(0, 40));
    if (s.size() > 40) out += "...";
    return "'" + out + "'";
}

// A face's index past the vertices, as the file writes it: "has an out-of-range vertex index
// 3000000000 (the file has 3 vertices)".
string out_of_range_index(string_view index, unsigned long long vertices)
{
    return "has an out-of-range vertex index " + string(index) + " (the file has " + std::to_string(vertices) +
           " vertices)";
}

// Whether a face property names its vertex index list, as OpenMesh's PLY reader takes it (either
// name).
bool is_ply_index_list(string_view name) { return name == "vertex_indices" || name == "vertex_index"; }

// Number of distinct values in a face's index list, without allocating for the usual short
// faces.
size_t distinct_count(const std::vector<long long>& v)
{
    if (v.size() > 16) {
        std::vector<long long> sorted(v);
        std::sort(sorted.begin(), sorted.end());
        return size_t(std::unique(sorted.begin(), sorted.end()) - sorted.begin());
    }
    size_t n = 0;
    for (size_t i = 0; i < v.size(); ++i)
        n += std::find(v.begin(), v.begin() + std::ptrdiff_t(i), v[i]) ==
             v.begin() + std::ptrdiff_t(i);
    return n;
}

// What the validation expects OpenMesh to deliver, checked after reading.
struct Expect {
    size_t add_face_calls = 0;       // faces the reader should hand to the importer
    size_t vertices = 0;             // 0: not checked
    size_t file_faces = 0;           // faces in the file (for messages and collapsed faces)
    bool faces_may_collapse = false; // STL: the reader skips faces whose corners coincide
    bool binary = false;
    // The vertex positions in double, in the reader's order, where the scan read them (ASCII OBJ,
    // OFF and PLY, binary PLY): OpenMesh reads floats, which at 5e6 (a mesh in geographic
    // coordinates) are 0.5 apart, so a torus there lost half its triangles as degenerate
    // (read_raw_mesh recentres).
    std::vector<glm::dvec3> positions;
    // Those positions are the file's 32-bit floats, or narrower (binary PLY of floats): exact,
    // but no finer than OpenMesh's (RawMesh::float_positions).
    bool positions_from_floats = false;
    // ASCII STL, checked word by word (scan_stl) and rewritten for OpenMesh (rewrite_ascii_stl).
    bool stl_ascii = false;
    // OFF whose counts line has no edge count ("4 2"): where to add " 0" in the bytes OpenMesh
    // parses, which otherwise takes the first vertex's x for it and shifts every later value.
    size_t off_counts_end = string_view::npos;
    // Bytes (offset, length) blanked for OpenMesh before it reads (rewrite_for_reader): ASCII OFF,
    // the face colours without a C header (it reads them only after one) and the vertex colours
    // before s t; ASCII PLY, the faces' texcoord lists.
    std::vector<std::pair<size_t, size_t>> blanks;
    // ASCII [ST]C[N]OFF: the values handed to OpenMesh separated by single spaces.
    bool off_single_spaces = false;
    // OBJ faces that repeat a vertex, by the number of their importer call: OpenMesh's reader
    // keeps only the first corner of each vertex (a polygon touching itself at a vertex became
    // another polygon, and the corners' texture coordinates, all passed on, matched none); the
    // importer takes their corners from here (0-based vertex indices, the file's order): face
    // k's call number repeating_calls[k], its corners repeating_corners[offsets[k], offsets[k+1]).
    std::vector<size_t> repeating_calls;
    std::vector<size_t> repeating_offsets{0};
    std::vector<std::uint32_t> repeating_corners;
    // A binary body rewritten for OpenMesh: the bytes from `binary_at` on, replaced by these
    // (rewrite_for_reader). Binary OFF in another layout than OpenMesh's
    // (binary_off_in_openmesh_layout); binary PLY without its faces' texcoord lists
    // (binary_ply_without_face_uvs).
    string binary_body;
    size_t binary_at = 0;
    // PLY: the vertex properties of u, v, s and t the reader is not given (ply_uv_names), renamed
    // by normalize_ply_header.
    std::vector<string> ply_unread_uv;
    bool ply_texture_uv = false; // read texture_u texture_v as u v (ply_texture_uv_alias)
    // PLY faces' corner UVs from a `texcoord` list (MeshLab's layout: u v per corner, in the
    // face's corner order), all faces' in file order; the list is taken out of what OpenMesh
    // reads (it took it for more indices): blanked in ASCII, and in binary the body rewritten
    // without it (binary_body).
    int ply_face_uv_list = -1; // the list's place among the face's properties
    std::vector<glm::vec2> ply_face_uvs;
};

void check_triangle_budget(const string& subject, unsigned long long triangles,
                           const MeshOptions& options)
{
    if (triangles > options.max_triangles)
        fail(subject, "has " + std::to_string(triangles) +
                          " triangles after triangulation; the limit is " +
                          std::to_string(options.max_triangles));
}

// Old Mac OS ended lines with CR alone. Neither the scan nor OpenMesh's readers take that for a
// line end: an OBJ read as one comment-like line "contains no faces", an OFF's counts were "on
// the line after 'OFF'" (found by an exploratory session). Say what it is instead.
void refuse_cr_line_ends(const string& subject, string_view text)
{
    const size_t cr = text.find('\r');
    if (cr != string_view::npos && cr + 1 < text.size() && text.find('\n') == string_view::npos)
        fail(subject, "uses CR line ends (classic Mac OS), which the reader does not take: convert them to LF or CR LF");
}

// ---- OBJ -----------------------------------------------------------------------------------

Expect scan_obj(const string& subject, string_view text, const MeshOptions& options)
{
    refuse_cr_line_ends(subject, text);
    Expect e;
    size_t nv = 0, nvt = 0, nvn = 0;
    long long max_v = 0, max_vt = 0, max_vn = 0;
    size_t max_v_line = 0, max_vt_line = 0, max_vn_line = 0;
    unsigned long long triangles = 0;
    std::vector<long long> face;
    LineReader lines(text);
    string_view line;
    string_view tok[4];
    while (lines.next(line)) {
        size_t i = 0;
        while (i < line.size() && is_space(line[i])) ++i;
        if (i == line.size() || line[i] == '#') continue;
        line.remove_prefix(i);
        const size_t key_end = std::min(
            line.size(), size_t(std::find_if(line.begin(), line.end(), is_space) - line.begin()));
        const string_view key = line.substr(0, key_end);
        const string_view rest = line.substr(key_end);
        if (key == "v") {
            const size_t n = tokenize(rest, tok, 3);
            glm::dvec3 p;
            if (n < 3 || !parse_finite_float(tok[0], &p.x) || !parse_finite_float(tok[1], &p.y) ||
                !parse_finite_float(tok[2], &p.z))
                fail(subject,
                     line_prefix(lines.line()) + "vertex position is not three finite numbers");
            e.positions.push_back(p);
            ++nv;
        } else if (key == "vt") {
            const size_t n = tokenize(rest, tok, 2);
            if (n < 2)
                fail(subject,
                     line_prefix(lines.line()) +
                         "texture coordinate is not two finite numbers (1D texture coordinates "
                         "are not supported)");
            // (A "nan" was called 1D.)
            for (int k = 0; k < 2; ++k)
                if (!parse_finite_float(tok[k]))
                    fail(subject, line_prefix(lines.line()) + "texture coordinate value " + shown(tok[k]) +
                                      " is not a finite number");
            ++nvt;
        } else if (key == "vn") {
            ++nvn;
        } else if (key == "f") {
            face.clear();
            size_t pos = 0;
            while (pos < rest.size()) {
                while (pos < rest.size() && is_space(rest[pos])) ++pos;
                if (pos == rest.size()) break;
                const size_t start = pos;
                while (pos < rest.size() && !is_space(rest[pos])) ++pos;
                const string_view corner = rest.substr(start, pos - start);
                // v, v/vt, v//vn or v/vt/vn
                const size_t s1 = corner.find('/');
                const string_view vs = corner.substr(0, s1);
                string_view ts, ns;
                if (s1 != string_view::npos) {
                    const size_t s2 = corner.find('/', s1 + 1);
                    ts = corner.substr(s1 + 1,
                                       s2 == string_view::npos ? string_view::npos : s2 - s1 - 1);
                    if (s2 != string_view::npos) ns = corner.substr(s2 + 1);
                }
                long long v = 0, t = 0, vn = 0;
                const bool numbers = parse_int(vs, v) && (ts.empty() || parse_int(ts, t)) && (ns.empty() || parse_int(ns, vn));
                // (An index 0 said so: it read "malformed face corner '0'"; an exploratory
                // session, forty-ninth.)
                if (numbers && (v == 0 || (!ts.empty() && t == 0) || (!ns.empty() && vn == 0)))
                    fail(subject, line_prefix(lines.line()) + "face corner " + shown(corner) +
                                      " has an index 0 (OBJ counts from 1, or from -1 back)");
                if (!numbers) fail(subject, line_prefix(lines.line()) + "malformed face corner " + shown(corner));
                if (v < 0) {
                    v += static_cast<long long>(nv) + 1;
                    if (v < 1)
                        fail(subject, line_prefix(lines.line()) + "vertex index " + string(vs) +
                                          " is out of range (" + std::to_string(nv) +
                                          " vertices so far)");
                } else if (v > max_v) {
                    max_v = v;
                    max_v_line = lines.line();
                }
                if (t < 0) {
                    t += static_cast<long long>(nvt) + 1;
                    if (t < 1)
                        fail(subject, line_prefix(lines.line()) + "texture coordinate index " +
                                          string(ts) + " is out of range (" + std::to_string(nvt) +
                                          " so far)");
                } else if (t > max_vt) {
                    max_vt = t;
                    max_vt_line = lines.line();
                }
                // Normal indices too, though the file's normals are not used (docs/mesh-input.md):
                // every index is checked, and one past the normals (`f 1//5` with one `vn`) was
                // taken without a word.
                if (vn < 0) {
                    vn += static_cast<long long>(nvn) + 1;
                    if (vn < 1)
                        fail(subject, line_prefix(lines.line()) + "normal index " + string(ns) +
                                          " is out of range (" + std::to_string(nvn) + " so far)");
                } else if (vn > max_vn) {
                    max_vn = vn;
                    max_vn_line = lines.line();
                }
                face.push_back(v);
            }
            if (face.size() < 3)
                fail(subject, line_prefix(lines.line()) + "a face needs at least 3 vertices");
            ++e.file_faces;
            // OpenMesh removes repeated vertices from a face and skips it when fewer than three
            // remain; such a face has no area anyway.
            const size_t distinct = distinct_count(face);
            if (distinct >= 3) {
                if (distinct < face.size()) {
                    e.repeating_calls.push_back(e.add_face_calls);
                    for (const long long v : face) e.repeating_corners.push_back(static_cast<std::uint32_t>(v - 1));
                    e.repeating_offsets.push_back(e.repeating_corners.size());
                }
                ++e.add_face_calls;
                triangles += face.size() - 2;
            }
        }
    }
    if (max_v > static_cast<long long>(nv))
        fail(subject, line_prefix(max_v_line) + "vertex index " + std::to_string(max_v) +
                          " is out of range (the file has " + std::to_string(nv) + " vertices)");
    if (max_vt > static_cast<long long>(nvt))
        fail(subject, line_prefix(max_vt_line) + "texture coordinate index " +
                          std::to_string(max_vt) + " is out of range (the file has " +
                          std::to_string(nvt) + ")");
    if (max_vn > static_cast<long long>(nvn))
        fail(subject, line_prefix(max_vn_line) + "normal index " + std::to_string(max_vn) +
                          " is out of range (the file has " + std::to_string(nvn) + ")");
    check_triangle_budget(subject, triangles, options);
    e.vertices = nv;
    return e;
}

// ---- OFF -----------------------------------------------------------------------------------

// Binary OFF is 32-bit words. Geomview, which defined the format, writes them big-endian and
// follows each face's indices with a colour count and that many floats; OpenMesh reads (and
// writes) little-endian words without the count. A layout fits when its faces, each of at least
// three indices below the vertex count (and at most four colour values), end exactly where the
// file does (or with only white space after).
struct BinaryOffLayout {
    bool big_endian = false;
    bool colour_counts = false;
};

class BinaryOffWords {
public:
    BinaryOffWords(string_view body, BinaryOffLayout layout) : body_(body), layout_(layout) {}
    size_t size() const { return body_.size() / 4; }
    std::uint32_t operator[](size_t i) const
    {
        unsigned char b[4];
        std::memcpy(b, body_.data() + 4 * i, 4);
        if (layout_.big_endian) std::reverse(b, b + 4);
        return std::uint32_t(b[3]) << 24 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[1]) << 8 | b[0];
    }

    // Calls keep(first, count) for each run of words to keep (counts, vertices, each face's
    // size and indices); false when the file does not fit the layout.
    template <class Keep>
    bool walk(size_t vertex_words, Keep&& keep) const
    {
        const size_t n = size();
        if (n < 3) return false;
        const std::uint64_t nv = (*this)[0], nf = (*this)[1];
        if (nv * vertex_words > n - 3 || nf > n) return false;
        keep(size_t(0), size_t(3) + size_t(nv) * vertex_words);
        size_t at = 3 + size_t(nv) * vertex_words;
        for (std::uint64_t f = 0; f < nf; ++f) {
            if (at >= n) return false;
            const std::uint32_t corners = (*this)[at];
            if (corners < 3 || corners > n - at - 1) return false;
            for (size_t c = 1; c <= corners; ++c)
                if ((*this)[at + c] >= nv) return false;
            keep(at, size_t(corners) + 1);
            at += size_t(corners) + 1;
            if (layout_.colour_counts) {
                if (at >= n || (*this)[at] > 4 || (*this)[at] > n - at - 1) return false;
                at += 1 + (*this)[at];
            }
        }
        for (size_t i = 4 * at; i < body_.size(); ++i)
            if (!std::isspace(static_cast<unsigned char>(body_[i]))) return false;
        return true;
    }

private:
    string_view body_;
    BinaryOffLayout layout_;
};

// The body rewritten in OpenMesh's layout when it is in another one that fits and OpenMesh's
// does not; empty otherwise (OpenMesh's own, or none: the checks after say what is wrong).
string binary_off_in_openmesh_layout(string_view body, size_t vertex_words)
{
    const auto none = [](size_t, size_t) {};
    if (BinaryOffWords(body, {}).walk(vertex_words, none)) return {};
    for (const BinaryOffLayout layout : {BinaryOffLayout{false, true}, BinaryOffLayout{true, false},
                                         BinaryOffLayout{true, true}}) {
        const BinaryOffWords words(body, layout);
        if (!words.walk(vertex_words, none)) continue;
        string out;
        out.reserve(body.size());
        words.walk(vertex_words, [&](size_t first, size_t count) {
            for (size_t i = first; i < first + count; ++i) {
                const std::uint32_t w = words[i];
                const char b[4] = {char(w & 0xff), char(w >> 8 & 0xff), char(w >> 16 & 0xff), char(w >> 24)};
                out.append(b, 4);
            }
        });
        return out;
    }
    return {};
}

// (CR line ends are refused by read_raw_mesh, before strip_off_comments.)
Expect scan_off(const string& subject, string_view text, const MeshOptions& options)
{
    Expect e;
    LineReader lines(text);
    string_view header;
    lines.next(header);
    string_view tok[4];
    const size_t n_head = tokenize(header, tok, 3);
    // [ST][C][N]OFF [BINARY]: the variants OpenMesh reads with 3D positions.
    string_view magic = n_head > 0 ? tok[0] : string_view();
    bool has_st = false, has_c = false, has_n = false;
    if (magic.substr(0, 2) == "ST") {
        has_st = true;
        magic.remove_prefix(2);
    }
    if (!magic.empty() && magic[0] == 'C') {
        has_c = true;
        magic.remove_prefix(1);
    }
    if (!magic.empty() && magic[0] == 'N') {
        has_n = true;
        magic.remove_prefix(1);
    }
    if (magic != "OFF") {
        if (n_head > 0 && tok[0].size() >= 3 && tok[0].substr(tok[0].size() - 3) == "OFF")
            fail(subject, "unsupported OFF variant " + shown(tok[0]) + " (only 3D [ST][C][N]OFF)");
        if (n_head == 0) // (a comment there was taken out: strip_off_comments)
            fail(subject, "line 1 is blank or a comment: the OFF header line must be the file's first");
        fail(subject, "does not start with an OFF header line");
    }
    if (n_head > 2 || (n_head == 2 && tok[1] != "BINARY"))
        fail(subject, "line 1: the counts must be on the line after " + shown(tok[0]) +
                          " (the reader expects the header alone on its first line)");
    e.binary = n_head == 2;
    const string header_name(tok[0]);
    const string vertex_layout = string("x y z") + (has_n ? " nx ny nz" : "") +
                                 (has_c ? " [colour: 0, 1, 3 or 4 numbers]" : "") +
                                 (has_st ? " s t" : "");
    const size_t body = lines.offset();
    const unsigned long long remaining = text.size() - body;

    unsigned long long nv = 0, nf = 0;
    if (e.binary) {
        if (remaining < 12) fail(subject, "binary OFF header is truncated");
        // OpenMesh reads binary face colours only when asked for them, and misreads every face
        // after the first colour when not; colours are not used here.
        if (has_c)
            fail(subject, "binary " + header_name +
                              " (colours) is not supported; use the ASCII variant or OFF BINARY");
        const size_t vertex_words = 3 + (has_n ? 3 : 0) + (has_st ? 2 : 0);
        e.binary_body = binary_off_in_openmesh_layout(text.substr(body), vertex_words);
        e.binary_at = body;
        const string_view words = e.binary_body.empty() ? text.substr(body) : string_view(e.binary_body);
        std::uint32_t counts[2];
        std::memcpy(counts, words.data(), sizeof counts);
        nv = counts[0];
        nf = counts[1];
        // Minimum sizes: 3 floats per vertex (and 3 for a normal, 2 for a texture coordinate),
        // a count and 3 indices per face.
        const unsigned long long vertex_bytes = 4 * vertex_words;
        const unsigned long long need = 12 + nv * vertex_bytes + nf * 16;
        // Counts that fit only read big-endian: Geomview's layout, with faces that do not fit it.
        const BinaryOffWords big(text.substr(body), {true, false});
        if (need > words.size() && 12 + std::uint64_t(big[0]) * vertex_bytes + std::uint64_t(big[1]) * 16 <= words.size())
            fail(subject, "big-endian binary OFF (Geomview's layout) whose faces do not end where the file does (a "
                          "face of fewer than 3 corners, an index out of range, more than 4 colour values, or "
                          "bytes after the last face)");
        if (need > words.size())
            fail(subject, "header claims " + std::to_string(nv) + " vertices and " +
                              std::to_string(nf) + " faces, more than a file of " +
                              std::to_string(text.size()) + " bytes can hold");
        // No layout fits: OpenMesh read what there was (a file cut short inside its last face drew
        // the faces before it, and a face claiming more corners than follow took the next words,
        // exit 0; found by an exploratory session).
        if (e.binary_body.empty() && !BinaryOffWords(text.substr(body), {}).walk(vertex_words, [](size_t, size_t) {}))
            fail(subject, "binary OFF whose faces do not end where the file does: it is cut short, or a face has "
                          "fewer than 3 corners, more corners than follow or an index out of range, or bytes "
                          "follow the last face");
        check_triangle_budget(subject, nf, options);
        e.add_face_calls = e.file_faces = nf;
        e.vertices = nv;
        return e;
    }

    string_view line;
    size_t n = 0;
    do {
        if (!lines.next(line)) fail(subject, "missing vertex and face counts after the OFF line");
        n = tokenize(line, tok, 3);
    } while (n == 0);
    long long cv = -1, cf = -1, ce = 0;
    if (n < 2 || !parse_int(tok[0], cv) || !parse_int(tok[1], cf) ||
        (n > 2 && !parse_int(tok[2], ce)) || cv < 0 || cf < 0 || cv > 0xffffffffLL ||
        cf > 0xffffffffLL)
        fail(subject, line_prefix(lines.line()) + "expected vertex, face and edge counts");
    // OpenMesh reads a vertex's position and takes the rest of its line for its colour and texture
    // coordinate: vertices on the counts' line (an OFF on one line) would be misread, and the scan
    // reads a vertex and a face per line. It said "header claims 3 vertices and 1 faces, more than a
    // file of 38 bytes can hold" (found by an exploratory session).
    if (n > 3)
        fail(subject, line_prefix(lines.line()) + "values after the vertex, face and edge counts: each vertex and "
                                                  "each face must be on a line of its own (the reader takes one to a line)");
    nv = static_cast<unsigned long long>(cv);
    nf = static_cast<unsigned long long>(cf);
    if (n == 2) e.off_counts_end = static_cast<size_t>(tok[1].data() + tok[1].size() - text.data());
    // Shortest text any vertex or face line can take, a value and a line end ("0\n"), so that only
    // counts no file of this size can hold fail here (nothing is allocated for them), and a short
    // line the checks below name: a face "0" said "header claims 3 vertices and 1 faces, more than
    // a file of 24 bytes can hold" when the bound was a triangle's 8 bytes.
    const unsigned long long left = text.size() - lines.offset();
    if ((nv + nf) * 2 > left + 1)
        fail(subject, "header claims " + std::to_string(nv) + " vertices and " +
                          std::to_string(nf) + " faces, more than a file of " +
                          std::to_string(text.size()) + " bytes can hold");
    check_triangle_budget(subject, nf, options);

    size_t extra_lines = 0, first_extra = 0; // plain vertex lines with values past x y z (nx ny nz)
    for (unsigned long long i = 0; i < nv; ++i) {
        string_view value[16];
        do {
            if (!lines.next(line))
                fail(subject, "file ends after " + std::to_string(i) + " of " + std::to_string(nv) +
                                  " vertices");
            n = tokenize(line, value, 16);
        } while (n == 0);
        glm::dvec3 p;
        if (n < 3 || !parse_finite_float(value[0], &p.x) || !parse_finite_float(value[1], &p.y) ||
            !parse_finite_float(value[2], &p.z))
            fail(subject,
                 line_prefix(lines.line()) + "vertex position is not three finite numbers");
        e.positions.push_back(p);
        // OpenMesh reads a normal's three numbers from the stream, past the line's end if it
        // must (a NOFF line without its normal shifted every value after it), and the rest from
        // the line: the colour (C, 0, 1, 3 or 4 numbers, told apart by their count) and the
        // texture coordinate (ST: with a colour the last two, else the first two), which a line
        // without them, or with words there, left undefined.
        const size_t fixed = has_n ? 6 : 3;
        const size_t rest = n >= fixed ? n - fixed : 0;
        // Without a colour, OpenMesh takes s t from the two values after x y z (nx ny nz) and
        // ignores the rest: a line with more ("x y z 0.9 s t") read (0.9, s), silently, where the
        // layout (and a colour-minded writer) puts them at the end (found by an exploratory
        // session, fifty-first): refused, as which two are meant is not known.
        const bool rest_ok =
            !has_st || (has_c ? rest == 2 || rest == 3 || rest == 5 || rest == 6 : rest == 2);
        if (n < fixed || !rest_ok || (has_c && has_st && n > 16)) // (16: the most values read here)
            fail(subject, line_prefix(lines.line()) + "a " + header_name + " vertex needs " +
                              vertex_layout + " (" + std::to_string(n) + " values here" +
                              (has_st && !has_c && rest > 2
                                   ? string("; a colour before s t needs a C in the header: STC") + (has_n ? "N" : "") + "OFF"
                                   : string()) +
                              ")");
        if (!has_c && !has_st && n > fixed && extra_lines++ == 0) first_extra = lines.line();
        const size_t st = has_c && has_st ? n - 2 : (has_c ? n : fixed); // (past the colour, if any)
        for (size_t k = 3; k < std::min<size_t>(n, 16); ++k)
            if ((k < st || (has_st && (k == st || k == st + 1))) && !parse_finite_float(value[k]))
                fail(subject, line_prefix(lines.line()) + "a " + header_name + " vertex needs " +
                                  vertex_layout + ", with numbers (" + shown(value[k]) + " here)");
        // The colour before s t: OpenMesh tells integers from floats by the first value's point
        // and reads the rest alike, so `1 0 0 0.5` (integers, then 0.5) left ".5" for s and read
        // (0.5, 0.2) for (0.2, 0.8), without a word (found by an exploratory session,
        // fifty-first). Colours are not used: blanked for it, which then reads none.
        if (has_c && has_st && st > fixed) {
            const size_t from = static_cast<size_t>(value[fixed].data() - text.data());
            e.blanks.emplace_back(from, static_cast<size_t>(value[st - 1].data() + value[st - 1].size() - text.data()) - from);
        }
    }
    // Values past a plain vertex's (a colour without a C in the header, say) are ignored by the
    // reader, and were without a word (found by an exploratory session, forty-ninth).
    if (extra_lines > 0)
        warn(subject + ": " + line_prefix(first_extra) + "a vertex line holds values past the " + vertex_layout + " of an " +
             header_name + " vertex" + (extra_lines > 1 ? " (and " + std::to_string(extra_lines - 1) + " more such lines)" : "") +
             ": ignored (a colour needs a C in the header, a texture coordinate ST)");
    // OpenMesh tells a colour's form by the line's remaining values, which it counts by single
    // spaces: a tab or two spaces between them read the colour as the texture coordinate.
    e.off_single_spaces = has_c;
    unsigned long long triangles = 0;
    std::vector<string_view> ftok;
    for (unsigned long long f = 0; f < nf; ++f) {
        do {
            if (!lines.next(line))
                fail(subject, "file ends after " + std::to_string(f) + " of " + std::to_string(nf) +
                                  " faces (does the header count more vertices or faces than the file holds? a "
                                  "vertex count one too large reads a face as a vertex)");
            n = tokenize(line, tok, 1);
        } while (n == 0);
        long long count = 0;
        if (!parse_int(tok[0], count) || count < 0)
            fail(subject, line_prefix(lines.line()) + "face " + std::to_string(f) +
                              " does not start with its vertex count");
        if (count < 3)
            fail(subject, line_prefix(lines.line()) + "face " + std::to_string(f) +
                              " has fewer than 3 vertices");
        if (static_cast<size_t>(count) + 1 > line.size())
            fail(subject,
                 line_prefix(lines.line()) + "face " + std::to_string(f) + " is truncated");
        ftok.resize(static_cast<size_t>(count) + 2);
        const size_t got = tokenize(line, ftok.data(), ftok.size());
        if (got < static_cast<size_t>(count) + 1)
            fail(subject,
                 line_prefix(lines.line()) + "face " + std::to_string(f) + " is truncated");
        // A face's colour (Geomview: 1, 3 or 4 numbers after its indices, in any OFF) is read by
        // OpenMesh only after a C header, which takes the rest of the line (and ignored words
        // there: checked alike); after another it took the colour for the next face's values.
        // Colours are not used: blanked for it. (The message said a COFF header was needed,
        // which is vertex colours; found by an exploratory session, fifty-first.)
        const size_t extra = got - static_cast<size_t>(count) - 1;
        if (extra > 0) {
            bool colour = extra == 1 || extra == 3 || extra == 4;
            if (colour) {
                ftok.resize(got);
                tokenize(line, ftok.data(), ftok.size());
            }
            for (size_t k = 0; colour && k < extra; ++k)
                colour = parse_finite_float(ftok[static_cast<size_t>(count) + 1 + k]);
            if (!colour)
                fail(subject, line_prefix(lines.line()) + "face " + std::to_string(f) + " has " +
                                  std::to_string(extra) + " value" + (extra == 1 ? "" : "s") +
                                  " after its vertex indices, which are not a colour (1, 3 or 4 numbers)");
            const string_view last = ftok[static_cast<size_t>(count)];
            const size_t from = static_cast<size_t>(last.data() + last.size() - text.data());
            if (!has_c) e.blanks.emplace_back(from, static_cast<size_t>(line.data() + line.size() - text.data()) - from);
        }
        for (long long k = 1; k <= count; ++k) {
            long long idx = 0;
            if (!parse_int(ftok[size_t(k)], idx) || idx < 0 ||
                static_cast<unsigned long long>(idx) >= nv)
                fail(subject, "face " + std::to_string(f) + " has an out-of-range vertex index " +
                                  shown(ftok[size_t(k)]) + " (the file has " + std::to_string(nv) +
                                  " vertices; line " + std::to_string(lines.line()) + ")");
        }
        triangles += static_cast<unsigned long long>(count) - 2;
    }
    // OpenMesh stops after the faces the header counts: a count too small dropped the faces after
    // them, silently (a cube with "8 1 0" drew one face, exit 0; found by an exploratory session).
    // Blank lines and comments may follow.
    while (lines.next(line))
        if (tokenize(line, tok, 1) > 0 && tok[0][0] != '#')
            fail(subject, line_prefix(lines.line()) + shown(line) + " follows the " + std::to_string(nf) +
                              " face" + (nf == 1 ? "" : "s") + " the header counts (is its face count too small?)");
    check_triangle_budget(subject, triangles, options);
    e.add_face_calls = e.file_faces = nf;
    e.vertices = nv;
    return e;
}

// ---- PLY -----------------------------------------------------------------------------------

struct PlyProperty {
    string name;
    string type;        // the scalar's type name (lists: the items')
    int size = 0;       // bytes of the scalar, or of each list item
    int count_size = 0; // > 0 for lists: bytes of the length prefix
    string count_type;  // lists: the length prefix's type name
};

struct PlyElement {
    string name;
    unsigned long long count = 0;
    std::vector<PlyProperty> properties;
};

int ply_type_size(string_view t)
{
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" ||
        t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

// A binary PLY scalar of type `type` at `at`, as a double.
double ply_binary_value(const char* at, string_view type, bool big_endian)
{
    unsigned char b[8];
    const int size = ply_type_size(type);
    std::memcpy(b, at, size_t(size));
    if (big_endian != (std::endian::native == std::endian::big)) std::reverse(b, b + size);
    const auto as = [&b]<typename T>(T) {
        T v;
        std::memcpy(&v, b, sizeof v);
        return double(v);
    };
    if (type == "char" || type == "int8") return as(std::int8_t{});
    if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
    if (type == "short" || type == "int16") return as(std::int16_t{});
    if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
    if (type == "int" || type == "int32") return as(std::int32_t{});
    if (type == "uint" || type == "uint32") return as(std::uint32_t{});
    if (type == "float" || type == "float32") return as(float{});
    return as(double{});
}

// Bytes of one item of a binary PLY element, its lists counted as their length prefix alone (the
// whole item for an element without lists).
size_t fixed_item_size(const PlyElement& el)
{
    size_t n = 0;
    for (const PlyProperty& p : el.properties) n += size_t(p.count_size > 0 ? p.count_size : p.size);
    return n;
}

// A binary PLY's vertex positions in double, from its body (after end_header): the elements
// before the vertex element have no lists (scan_ply refuses lists outside the face element, which
// comes after the vertices), so the vertices start at a fixed place and are all the same size.
// Empty when the body is too short for them (the reader then says what is wrong).
std::vector<glm::dvec3> binary_ply_positions(string_view body, const std::vector<PlyElement>& elements,
                                             const PlyElement& vertex, bool big_endian)
{
    size_t at = 0;
    for (const PlyElement& el : elements) {
        if (&el == &vertex) break;
        at += fixed_item_size(el) * el.count;
    }
    const size_t size = fixed_item_size(vertex);
    if (at > body.size() || (body.size() - at) / size < vertex.count) return {};
    std::vector<glm::dvec3> positions(vertex.count, glm::dvec3(0.0));
    size_t offset = 0;
    for (const PlyProperty& p : vertex.properties) {
        const int axis = p.name == "x" ? 0 : p.name == "y" ? 1 : p.name == "z" ? 2 : -1;
        if (axis >= 0)
            for (size_t i = 0; i < vertex.count; ++i)
                positions[i][axis] = ply_binary_value(body.data() + at + i * size + offset, p.type, big_endian);
        offset += size_t(p.size);
    }
    return positions;
}

// Where a binary PLY's elements end in its body (after end_header), walking its lists by their
// counts; a body that ends before them is refused, naming the element and item. A
// list count that is negative, or that needs more bytes than the file has left, is refused here,
// naming the item: OpenMesh's reader sizes a vector from it before reading a value (a face of -1
// or 1e9 corners took minutes and gigabytes; found by an exploratory session).
// Each face's vertex indices are checked against `vertices` on the way, and one past them is said
// as the file has it: the reader's 32-bit handles showed an unsigned index past 2^31 as a negative
// number (3000000000 as "-1294967296").
[[noreturn]] void short_binary_ply_face(const string& subject, string_view body, const std::vector<PlyElement>& elements,
                                        bool big_endian, int face_uv_list, unsigned long long face,
                                        unsigned long long corners);

// A PLY face's texcoord list (Expect::ply_face_uv_list) whose length is not u v for each corner.
string texcoord_length_problem(unsigned long long face, long long count, long long corners)
{
    return "face " + std::to_string(face) + "'s texcoord list counts " + std::to_string(count) + " values; its " +
           std::to_string(corners) + " corners call for " + std::to_string(2 * corners) + " (u v each)";
}

size_t binary_ply_end(const string& subject, string_view body, const std::vector<PlyElement>& elements,
                      bool big_endian, unsigned long long vertices, int face_uv_list, bool probing = false)
{
    size_t at = 0;
    // (It returned the body's size and left the reader to fail: "the reader reported a failure",
    // or a face misread against vertices a header count too large had shifted; found by an
    // exploratory session, thirty-third.)
    const auto ends_inside = [&](const PlyElement& el, unsigned long long i) {
        fail(subject, "binary PLY ends inside its " + el.name + " " + std::to_string(i) + " of " +
                          std::to_string(el.count) + " (cut short, or a count too large?)");
    };
    for (const PlyElement& el : elements) {
        // An element without lists in one step: items of fixed size (none at all for an element
        // without properties, which a header may count by the billion: 4e9 empty items took 1.5 s
        // one by one; found by a review).
        if (std::none_of(el.properties.begin(), el.properties.end(),
                         [](const PlyProperty& p) { return p.count_size != 0; })) {
            const unsigned long long stride = fixed_item_size(el);
            if (stride != 0 && el.count > (body.size() - at) / stride)
                fail(subject, "binary PLY ends inside its " + el.name + " element: " + std::to_string(el.count) +
                                  " of " + std::to_string(stride) + " bytes each need " +
                                  std::to_string(el.count * stride) + ", and " + std::to_string(body.size() - at) +
                                  " are left (cut short, or a count too large?)");
            at += size_t(stride * el.count);
            continue;
        }
        for (unsigned long long i = 0; i < el.count; ++i) {
            const size_t face_start = at; // (a face's first property is its index list: scan_ply)
            for (size_t k = 0; k < el.properties.size(); ++k) {
                const PlyProperty& p = el.properties[k];
                if (p.count_size == 0) {
                    at += size_t(p.size);
                } else {
                    if (at + size_t(p.count_size) > body.size()) ends_inside(el, i);
                    const double count = ply_binary_value(body.data() + at, p.count_type, big_endian);
                    at += size_t(p.count_size);
                    const size_t left = body.size() - at;
                    if (!(count >= 0.0) || count > double(left / size_t(p.size)))
                        fail(subject, "binary PLY " + el.name + " " + std::to_string(i) + ": its " + p.name +
                                          " list counts " + std::to_string(static_cast<long long>(count)) +
                                          (count < 0.0 ? string(" entries (a negative count)")
                                                       : " entries of " + std::to_string(p.size) + " byte" +
                                                             (p.size == 1 ? "" : "s") + ", more than the " +
                                                             std::to_string(left) + " byte" + (left == 1 ? "" : "s") +
                                                             " left in the file (truncated, or a bad count?)"));
                    if (el.name == "face" && is_ply_index_list(p.name) && count < 3.0) {
                        if (probing) fail(subject, "a face of fewer than 3 vertices");
                        short_binary_ply_face(subject, body, elements, big_endian, face_uv_list, i,
                                              static_cast<unsigned long long>(count));
                    }
                    // The texcoord list (Expect::ply_face_uv_list), u v for each corner: said at its
                    // face here, where a wrong count would put the next face's start off (it was said
                    // at the face after it, as that face's fault).
                    if (el.name == "face" && static_cast<int>(k) == face_uv_list) {
                        const double corners = ply_binary_value(body.data() + face_start, el.properties[0].count_type, big_endian);
                        if (count != 2.0 * corners)
                            fail(subject, "binary PLY " + texcoord_length_problem(i, static_cast<long long>(count),
                                                                                  static_cast<long long>(corners)));
                    }
                    if (el.name == "face" && is_ply_index_list(p.name))
                        for (size_t c = 0; c < size_t(count); ++c) {
                            const double index = ply_binary_value(body.data() + at + c * size_t(p.size), p.type, big_endian);
                            if (index < 0.0 || index >= double(vertices))
                                fail(subject, "face " + std::to_string(i) + " " +
                                                  out_of_range_index(std::to_string(static_cast<long long>(index)), vertices));
                        }
                    at += size_t(count) * size_t(p.size);
                }
                if (at > body.size()) ends_inside(el, i);
            }
        }
    }
    return at;
}

// A binary PLY face of fewer than 3 vertices. It may be the file's own, or a header that counts
// more vertices than the body holds: the vertices then take the first faces' bytes, and the faces
// are read shifted, where the high bytes of small indices read as counts of 0. The second is said
// only where it is so: where the body reads whole, every face of 3 vertices or more and every
// index in range, with up to 64 vertices fewer than the header counts. (Every such face had the
// question "does the header count more vertices than the file holds?", a face "0" or "2 0 1"
// written as such too; found by an exploratory session.)
void short_binary_ply_face(const string& subject, string_view body, const std::vector<PlyElement>& elements,
                           bool big_endian, int face_uv_list, unsigned long long face, unsigned long long corners)
{
    const string problem = "face " + std::to_string(face) + " has fewer than 3 vertices (it lists " + std::to_string(corners) + ")";
    const auto vertex = std::find_if(elements.begin(), elements.end(),
                                     [](const PlyElement& el) { return el.name == "vertex"; });
    if (vertex != elements.end()) {
        std::vector<PlyElement> fewer = elements;
        PlyElement& v = fewer[size_t(vertex - elements.begin())];
        for (unsigned long long k = 1; k <= std::min<unsigned long long>(64, vertex->count); ++k) {
            v.count = vertex->count - k;
            bool whole = false;
            try {
                const size_t end = binary_ply_end(subject, body, fewer, big_endian, v.count, face_uv_list, true);
                whole = std::all_of(body.begin() + std::ptrdiff_t(end), body.end(), is_space);
            } catch (const Error&) {
            }
            if (whole)
                fail(subject, problem + "; the body reads whole with " + std::to_string(v.count) + " vertices: " +
                                  "does the header count " + std::to_string(k) + " more than the file holds?");
        }
    }
    fail(subject, problem);
}

// A list's count type as OpenMesh's reader is given it (normalize_ply_header): one it does not
// take is renamed to the one of the same size it takes (ushort, short, int16 → uint16; int32,
// uint, uint32 → int; char, int8 → uchar: the same bytes, read as counts).
string_view ply_count_type_as_read(string_view type)
{
    static const std::pair<string_view, string_view> same_size[] = {
        {"ushort", "uint16"}, {"short", "uint16"}, {"int16", "uint16"}, {"int32", "int"},
        {"uint", "int"},      {"uint32", "int"},   {"char", "uchar"},   {"int8", "uchar"}};
    for (const auto& [from, to] : same_size)
        if (type == from) return to;
    return type;
}

// Whether OpenMesh's PLY reader reads `element`'s property `name` as a colour (normalize_ply_header).
bool is_ply_colour(string_view element, string_view name)
{
    static const string_view kVertex[] = {"red",         "green",         "blue", "alpha",
                                          "diffuse_red", "diffuse_green", "diffuse_blue"};
    if (element == "vertex") return std::find(std::begin(kVertex), std::end(kVertex), name) != std::end(kVertex);
    return element == "face" && (name == "red" || name == "green" || name == "blue" || name == "alpha");
}

// The texture coordinates a PLY vertex element's scalar properties `names` give the reader.
// OpenMesh's reads u and s as the first coordinate and v and t as the second, a name later in the
// header over one before it, and one without the other as a pair whose other half is 0: a file
// with u v and s t was read with whichever pair came last, and one with u alone as (u, 0), without
// a word (found by an exploratory session, forty-first). So a whole pair is read, u v before s t
// (or one first and one second coordinate, u t or s v), and the other names of the four are not
// (renamed unread_, normalize_ply_header); half a pair is not read at all, and UVs are generated.
// MeshLab's names for them, texture_u and texture_v, are read as u v where the vertex has neither
// of those pairs (renamed by normalize_ply_header; they were reported as not read and UVs
// generated; found by an exploratory session, fifty-first).
bool ply_texture_uv_alias(const std::vector<PlyProperty>& vertex)
{
    const auto has = [&](string_view n) {
        return std::any_of(vertex.begin(), vertex.end(), [&](const PlyProperty& p) { return p.count_size == 0 && p.name == n; });
    };
    return has("texture_u") && has("texture_v") && !has("u") && !has("v") && !has("s") && !has("t");
}

struct PlyUvNames {
    std::vector<string> unread; // of u, v, s and t, those the reader is not given
    string why;                 // what the scan warns, or empty
};

PlyUvNames ply_uv_names(const std::vector<string_view>& names)
{
    const auto has = [&](string_view n) { return std::find(names.begin(), names.end(), n) != names.end(); };
    const bool u = has("u"), v = has("v"), s = has("s"), t = has("t");
    PlyUvNames out;
    const auto leave_out = [&](std::initializer_list<string_view> which) {
        for (const string_view n : which)
            if (has(n)) out.unread.emplace_back(n);
    };
    if (u && v && (s || t)) {
        leave_out({"s", "t"});
        const string other = s && t ? "s t" : (s ? "s" : "t");
        out.why = "vertex properties u v and " + other + ": u v are read as texture coordinates, " + other + " not";
    } else if (s && t && (u || v)) {
        leave_out({"u", "v"});
        const string other = u ? "u" : "v";
        out.why = "vertex properties s t and " + other + ": s t are read as texture coordinates, " + other + " not";
    } else if ((u || s) != (v || t)) {
        leave_out({"u", "v", "s", "t"});
        const string present = u && s ? "u and s" : (u ? "u" : (s ? "s" : (v && t ? "v and t" : (v ? "v" : "t"))));
        out.why = "vertex propert" + string(present.size() > 1 ? "ies " : "y ") + present + " without " +
                  (u || s ? "v or t" : "u or s") + ": not read as texture coordinates";
    }
    return out;
}

// A PLY header as OpenMesh's reader takes it, rewritten after the scan has checked it (whose
// messages count the file's own lines): white space at a header line's end is dropped (after
// `end_header` it put a binary body a byte off, and after a list property the reader failed
// without a word of why; found by an exploratory session, thirty-third); every list's count type
// is one the reader takes (ply_count_type_as_read); and comment, obj_info and blank lines go.
// The reader takes the words of an obj_info line as keywords (`element` there spun its header
// loop forever), and finds a binary body 12 bytes past the end of the last word it read before
// end_header, where a comment it reads to the line's end, or a blank line, put the body a byte
// or more off ("face 0 has fewer than 3 vertices"): both were refused until the thirty-fourth
// session, and a review found them refusing files the reader would have read right (an
// obj_info line last; a comment last in a CR LF header). Colours, which nothing here uses, are
// renamed so that the reader skips them as it skips any property it does not know (by their
// size, or a word of ASCII): it read them itself, a binary double as an integer it could not
// convert, with a line on stderr for every value and the rest of the file misread ("face 0 has
// fewer than 3 vertices"), and an ASCII one into an integer, which "255.0" or "0.5" misaligned
// (found by an exploratory session, thirty-eighth). So are the vertex's texture-coordinate
// properties the scan leaves unread (`unread`: Expect::ply_unread_uv, ply_uv_names), and MeshLab's
// texture_u texture_v become u v where `texture_uv` (ply_texture_uv_alias). The faces' texcoord
// list goes where `face_uvs` (Expect::ply_face_uv_list: read by the scan, taken out of the body).
void normalize_ply_header(string& text, const std::vector<string>& unread, bool texture_uv, bool face_uvs)
{
    const size_t header_end = [&] {
        LineReader lines(text);
        string_view line, tok[1];
        while (lines.next(line))
            if (tokenize(line, tok, 1) > 0 && tok[0] == "end_header") return lines.offset();
        return string::npos;
    }();
    if (header_end == string::npos) return; // (the scan says so)
    const auto unread_uv = [&](string_view element, string_view name) {
        return element == "vertex" && std::find(unread.begin(), unread.end(), name) != unread.end();
    };
    // OpenMesh's binary reader finds the body 12 bytes past the end of the header's last word
    // before end_header ("\nend_header\n"; 14 where the first of them is CR LF): so end_header is
    // written from the line's start, with the line end of the line before it (an indented one, or
    // one whose line end differed, put the body a byte or two off; found by a review).
    string out;
    out.reserve(header_end);
    LineReader lines(string_view(text).substr(0, header_end));
    string_view line;
    bool previous_cr = false;
    string_view element; // the element whose properties these are
    while (lines.next(line)) {
        const bool cr = !line.empty() && line.back() == '\r';
        string_view body = cr ? line.substr(0, line.size() - 1) : line;
        while (!body.empty() && is_space(body.back())) body.remove_suffix(1); // (\v and \f too: a review)
        string_view tok[6];
        string fixed(body);
        const size_t words = tokenize(body, tok, 6);
        if (words == 0 || tok[0] == "comment" || tok[0] == "obj_info") continue;
        if (words == 3 && tok[0] == "element") element = tok[1];
        if (face_uvs && element == "face" && words == 5 && tok[0] == "property" && tok[1] == "list" && tok[4] == "texcoord")
            continue;
        if (words == 5 && tok[0] == "property" && tok[1] == "list" && ply_count_type_as_read(tok[2]) != tok[2])
            fixed = "property list " + string(ply_count_type_as_read(tok[2])) + " " + string(tok[3]) + " " + string(tok[4]);
        if (words == 3 && tok[0] == "property" && (is_ply_colour(element, tok[2]) || unread_uv(element, tok[2])))
            fixed = "property " + string(tok[1]) + " unread_" + string(tok[2]);
        if (words == 3 && tok[0] == "property" && texture_uv && element == "vertex" &&
            (tok[2] == "texture_u" || tok[2] == "texture_v"))
            fixed = "property " + string(tok[1]) + " " + string(tok[2].substr(8));
        const bool last = words == 1 && tok[0] == "end_header";
        if (last) fixed = "end_header";
        out += fixed;
        if (last ? previous_cr : cr) out += '\r';
        if (lines.offset() <= header_end && text[lines.offset() - 1] == '\n') out += '\n';
        previous_cr = cr;
    }
    // (The header alone is rewritten, where it changed: the body may be hundreds of megabytes.)
    if (string_view(text).substr(0, header_end) != out) text.replace(0, header_end, out);
}

// An ASCII PLY face line `line` (line `number` of `text`, face `f`, `values` words) whose face has
// a texcoord list (Expect::ply_face_uv_list): its lists walked by their counts, the list's u v
// pairs kept (two for each of the face's corners, vertex_indices' count) and the list blanked.
// Returns the face's corner count.
long long ascii_face_uvs(const string& subject, size_t number, string_view line, size_t values, const PlyElement& face,
                    unsigned long long f, string_view text, Expect& e)
{
    std::vector<string_view> word(values);
    tokenize(line, word.data(), values);
    size_t at = 0;
    long long corners = -1;
    for (size_t k = 0; k < face.properties.size(); ++k) {
        long long count = 1;
        if (face.properties[k].count_size > 0 && (at >= values || !parse_int(word[at], count) || count < 0))
            fail(subject, line_prefix(number) + "face line's " + face.properties[k].name + " list " +
                              (at >= values ? string("is missing") : "count " + shown(word[at]) + " is not a whole number"));
        if (face.properties[k].count_size == 0) {
            ++at;
            continue;
        }
        if (static_cast<unsigned long long>(count) > values - at - 1)
            fail(subject, line_prefix(number) + "face line has " + std::to_string(values) + " values; its " +
                              face.properties[k].name + " list counts " + std::to_string(count) + ", past the line's end");
        if (k == 0) corners = count;
        if (static_cast<int>(k) == e.ply_face_uv_list) {
            if (count != 2 * corners) fail(subject, line_prefix(number) + texcoord_length_problem(f, count, corners));
            for (size_t c = 0; c < size_t(corners); ++c) {
                double uv[2];
                for (size_t j = 0; j < 2; ++j)
                    if (!parse_finite_float(word[at + 1 + 2 * c + j], &uv[j]))
                        fail(subject, line_prefix(number) + "face " + std::to_string(f) + "'s texcoord value " +
                                          shown(word[at + 1 + 2 * c + j]) + " is not a finite number");
                e.ply_face_uvs.emplace_back(uv[0], uv[1]);
            }
            const string_view last = word[at + size_t(count)];
            const size_t from = size_t(word[at].data() - text.data());
            e.blanks.emplace_back(from, size_t(last.data() + last.size() - text.data()) - from);
        }
        at += 1 + size_t(count);
    }
    if (at != values)
        fail(subject, line_prefix(number) + "face line has " + std::to_string(values) + " values; its properties call for " +
                          std::to_string(at) + " (each list: its count, then that many values)");
    return corners;
}

// A binary PLY body (checked by binary_ply_end) without its faces' texcoord list, whose u v pairs
// (two for each of the face's corners) go to Expect::ply_face_uvs.
string binary_ply_without_face_uvs(const string& subject, string_view body, const std::vector<PlyElement>& elements,
                                   bool big_endian, Expect& e)
{
    string out;
    out.reserve(body.size());
    size_t at = 0;
    for (const PlyElement& el : elements) {
        if (el.name != "face") {
            // (Lists are refused outside the face element: fixed-size items.)
            const size_t bytes = fixed_item_size(el) * size_t(el.count);
            out.append(body.substr(at, bytes));
            at += bytes;
            continue;
        }
        for (unsigned long long i = 0; i < el.count; ++i) {
            size_t corners = 0;
            for (size_t k = 0; k < el.properties.size(); ++k) {
                const PlyProperty& p = el.properties[k];
                const size_t from = at;
                if (p.count_size == 0) {
                    at += size_t(p.size);
                    out.append(body.substr(from, size_t(p.size)));
                    continue;
                }
                const size_t count = size_t(ply_binary_value(body.data() + at, p.count_type, big_endian));
                at += size_t(p.count_size) + count * size_t(p.size);
                if (k == 0) corners = count;
                if (static_cast<int>(k) != e.ply_face_uv_list) {
                    out.append(body.substr(from, at - from));
                    continue;
                }
                // (Its length, two values for each corner, checked by binary_ply_end.)
                const char* value = body.data() + from + size_t(p.count_size);
                for (size_t c = 0; c < corners; ++c) {
                    const double u = ply_binary_value(value + 2 * c * size_t(p.size), p.type, big_endian);
                    const double v = ply_binary_value(value + (2 * c + 1) * size_t(p.size), p.type, big_endian);
                    if (!std::isfinite(u) || !std::isfinite(v))
                        fail(subject, "binary PLY face " + std::to_string(i) + "'s texcoord list holds a value that is "
                                                                               "not a finite number");
                    e.ply_face_uvs.emplace_back(u, v);
                }
            }
        }
    }
    out.append(body.substr(std::min(at, body.size())));
    return out;
}

Expect scan_ply(const string& subject, string_view text, const MeshOptions& options)
{
    refuse_cr_line_ends(subject, text);
    Expect e;
    LineReader lines(text);
    string_view line;
    string_view tok[6];
    lines.next(line);
    if (tokenize(line, tok, 1) != 1 || tok[0] != "ply") fail(subject, "does not start with 'ply'");
    bool ascii = false;
    bool big_endian = false;
    bool have_format = false;
    std::vector<PlyElement> elements;
    bool ended = false;
    while (lines.next(line)) {
        const size_t n = tokenize(line, tok, 6);
        if (n == 0) continue;
        const string where = line_prefix(lines.line());
        // OpenMesh reads the header as a stream of words, not lines: the first three words after
        // "ply" as format, type and version, then keywords, each followed by the words it expects
        // (a number after "element NAME"). A word that does not parse as its number leaves the
        // stream failed and its header loop spinning forever (found by tests/fuzz/fuzz_mesh), so
        // every line must hold exactly the words OpenMesh will take from it.
        if (tok[0] == "comment" || tok[0] == "obj_info") continue; // (dropped before the reader sees them: normalize_ply_header)
        if (!have_format && tok[0] != "format")
            fail(subject, where + "expected the format line right after 'ply'");
        if (tok[0] == "end_header") {
            if (n != 1) fail(subject, where + "unexpected words after end_header");
            ended = true;
            break;
        } else if (tok[0] == "format") {
            // A second one was half read: its version checked, its type dropped (found by an
            // exploratory session, forty-eighth).
            if (have_format) fail(subject, where + "a second format line (a header has one, right after 'ply')");
            double version = 0.0;
            if (n != 3 || !parse_finite_float(tok[2], &version))
                fail(subject, where + "malformed format line (expected 'format TYPE 1.0')");
            // 1.0 is the only version there is; a file that says another may mean anything
            // (taken without a word until found by an exploratory session, forty-seventh).
            if (version != 1.0)
                fail(subject, where + "PLY version " + shown(tok[2]) + " is not 1.0, the only one there is");
            if (tok[1] == "ascii")
                ascii = true;
            else if (tok[1] == "binary_big_endian")
                big_endian = true;
            else if (tok[1] != "binary_little_endian" && tok[1] != "binary_big_endian")
                fail(subject, where + "unknown PLY format " + shown(tok[1]));
            have_format = true;
        } else if (tok[0] == "element") {
            long long count = -1;
            if (n != 3 || !parse_int(tok[2], count) || count < 0 || count > 0xffffffffLL)
                fail(subject, where + "malformed element line");
            if (tok[1] == "vertex" || tok[1] == "face")
                for (const PlyElement& el : elements)
                    if (el.name == tok[1]) fail(subject, where + "element '" + string(tok[1]) + "' declared twice");
            elements.push_back({string(tok[1]), static_cast<unsigned long long>(count), {}});
        } else if (tok[0] == "property") {
            if (elements.empty()) fail(subject, where + "property before any element");
            PlyProperty p;
            if (n != (n > 1 && tok[1] == "list" ? 5u : 3u))
                fail(subject, where + "malformed property line");
            if (n >= 5 && tok[1] == "list") {
                p.count_size = ply_type_size(tok[2]);
                p.count_type = string(tok[2]);
                p.size = ply_type_size(tok[3]);
                p.type = string(tok[3]);
                p.name = string(tok[4]);
            } else if (n >= 3) {
                p.size = ply_type_size(tok[1]);
                p.type = string(tok[1]);
                p.name = string(tok[2]);
            }
            if (p.size == 0 || (tok[1] == "list" && p.count_size == 0))
                fail(subject, where + "malformed or unknown property type");
            // (OpenMesh's reader then failed without saying why: found by an exploratory session.)
            for (const PlyProperty& q : elements.back().properties)
                if (q.name == p.name)
                    fail(subject, where + "element '" + elements.back().name + "' declares property '" + p.name +
                                      "' twice");
            elements.back().properties.push_back(p);
        } else {
            fail(subject, where + "unexpected header line " + shown(line));
        }
    }
    if (!ended) fail(subject, "PLY header has no end_header line");
    if (!have_format) fail(subject, "PLY header has no format line");

    const PlyElement* vertex = nullptr;
    const PlyElement* face = nullptr;
    for (const PlyElement& el : elements) {
        if (el.name == "vertex") vertex = &el;
        if (el.name == "face") face = &el;
    }
    if (!vertex) fail(subject, "PLY header declares no vertex element");
    // OpenMesh reads the faces as they come, against the vertices read so far: faces first read as
    // "face 0 has an out-of-range vertex index 0 (the file has 0 vertices)" (found by an
    // exploratory session).
    if (face && face < vertex)
        fail(subject, "PLY element 'face' comes before 'vertex', which the reader cannot take (put the vertices first)");
    bool has_xyz[3] = {false, false, false};
    size_t xyz_at[3] = {0, 0, 0}; // the properties' places on an ASCII vertex line
    for (size_t k = 0; k < vertex->properties.size(); ++k) {
        const PlyProperty& p = vertex->properties[k];
        if (p.count_size == 0 && (p.name == "x" || p.name == "y" || p.name == "z")) {
            has_xyz[p.name[0] - 'x'] = true;
            xyz_at[p.name[0] - 'x'] = k;
        }
    }
    if (!has_xyz[0] || !has_xyz[1] || !has_xyz[2])
        fail(subject, "PLY vertex element lacks an x, y or z property");
    // OpenMesh's binary reader converts only floats and doubles to the floats of a position, a
    // normal or a texture coordinate: a short x printed "unsupported conversion type to float"
    // for every value and misread the rest (30,000 lines for a grid of 10,000 vertices; found by
    // an exploratory session, thirty-third). ASCII values are read as numbers, whatever their type.
    e.ply_texture_uv = ply_texture_uv_alias(vertex->properties);
    if (!ascii)
        for (const PlyProperty& p : vertex->properties) {
            static const string_view kFloats[] = {"x", "y", "z", "nx", "ny", "nz", "u", "v", "s", "t"};
            const bool read_as_float = std::find(std::begin(kFloats), std::end(kFloats), p.name) != std::end(kFloats) ||
                                       (e.ply_texture_uv && (p.name == "texture_u" || p.name == "texture_v"));
            if (read_as_float && p.count_size == 0 && p.type != "float" && p.type != "float32" && p.type != "double" &&
                p.type != "float64")
                fail(subject, "binary PLY vertex property '" + p.name + "' is a " + p.type +
                                  ", which the reader cannot take (positions, normals and texture coordinates: "
                                  "float or double; ASCII PLY takes any)");
        }
    if ((!face || face->count == 0) &&
        std::any_of(elements.begin(), elements.end(), [](const PlyElement& el) { return el.name == "tristrips"; }))
        fail(subject, "has triangle strips (element 'tristrips') and no face element: only faces are read");
    if (!face || face->count == 0) fail(subject, "contains no faces");
    // Layouts OpenMesh 9.0's reader misreads without a word (it read the file's triangle (0,1,2)
    // as (3,0,1) or (1,3,0)): a list in any element but the face, a face property before its
    // vertex_indices.
    for (const PlyElement& el : elements)
        for (const PlyProperty& p : el.properties) {
            // OpenMesh 9.0's reader takes uchar, uint8, uint16 and int for a list's count and failed
            // on the others with no word of why ("the reader reported a failure"; found by an
            // exploratory session); integer counts are renamed to those (normalize_ply_header).
            const string_view read_as = ply_count_type_as_read(p.count_type);
            if (p.count_size > 0 && read_as != "uchar" && read_as != "uint8" && read_as != "uint16" && read_as != "int")
                fail(subject, "PLY " + el.name + " list '" + p.name + "' counts its entries in a " + p.count_type +
                                  ", which the reader cannot take (an integer type)");
            if (&el != face && p.count_size > 0 && el.count > 0) // (an empty one holds nothing to misread)
                fail(subject, "PLY element '" + el.name + "' has a list property '" + p.name +
                                  "', which the reader cannot skip (lists are read in the face element only)");
        }
    bool has_indices = false;
    for (const PlyProperty& p : face->properties) {
        const bool indices = is_ply_index_list(p.name);
        // MeshLab's per-corner texture coordinates: read by the scan (one such list).
        if (p.count_size > 0 && p.name == "texcoord" && has_indices && e.ply_face_uv_list < 0) {
            e.ply_face_uv_list = static_cast<int>(&p - face->properties.data());
            continue;
        }
        if (!has_indices && !indices)
            fail(subject, "PLY face property '" + p.name +
                              "' comes before vertex_indices, which the reader cannot take (put it after)");
        // A second list of indices (either name): the reader took each list of a face for a face
        // of its own, and drew another mesh with exit 0 (a tetrahedron whose faces each had two
        // lists; found by an exploratory session, forty-second).
        if (p.count_size > 0 && indices && has_indices)
            fail(subject, "PLY face element has a second vertex index list '" + p.name +
                              "', which the reader would take for more faces (one list of indices per face)");
        if (p.count_size > 0 && indices) has_indices = true;
        // The binary reader converts only integers to indices: float ones printed "unsupported
        // conversion type to integral" for every index and misread the rest ("face 1 has fewer
        // than 3 vertices"; found by an exploratory session, thirty-eighth).
        if (!ascii && p.count_size > 0 && indices &&
            (p.type == "float" || p.type == "float32" || p.type == "double" || p.type == "float64"))
            fail(subject, "binary PLY face list '" + p.name + "' holds " + p.type +
                              " values, which the reader cannot take as vertex indices (an integer type)");
        // OpenMesh's reader takes a face's other lists for more indices and fails, saying a face
        // "has fewer than 3 vertices": name the list instead (MeshLab writes per-face UVs so).
        if (p.count_size > 0 && !indices)
            fail(subject, "PLY face element has a list property '" + p.name +
                              "' besides vertex_indices, which is not read (texture coordinates are read "
                              "per vertex, as u v or s t, or per face as one texcoord list)");
    }
    if (!has_indices) fail(subject, "PLY face element lacks a vertex_indices list");
    // Texture coordinates under names the reader does not take are dropped: say which, rather
    // than only that the file has none (UVs are then generated).
    std::string ignored_uv;
    bool has_uv = false;
    std::vector<string_view> scalars;
    for (const PlyProperty& p : vertex->properties)
        if (p.count_size == 0) scalars.emplace_back(p.name);
    const PlyUvNames uv = ply_uv_names(scalars);
    if (!uv.why.empty()) warn(subject + ": " + uv.why);
    e.ply_unread_uv = uv.unread;
    for (const PlyProperty& p : vertex->properties) {
        if (p.name == "u" || p.name == "v" || p.name == "s" || p.name == "t")
            has_uv = has_uv || std::find(uv.unread.begin(), uv.unread.end(), p.name) == uv.unread.end();
        else if (e.ply_texture_uv && (p.name == "texture_u" || p.name == "texture_v"))
            has_uv = true;
        else if (p.name.find("tex") != std::string::npos)
            ignored_uv += (ignored_uv.empty() ? "" : ", ") + p.name;
    }
    if (!has_uv && !ignored_uv.empty())
        warn(subject + ": vertex properties " + ignored_uv +
             " are not read as texture coordinates (u v or s t are)");

    // Smallest body the header allows: binary sizes, or two characters per ASCII value, a list
    // counting as its count alone. A true lower bound, so that only counts no file of this size can
    // hold fail here, and a short face the checks after name: with three indices a list, a face
    // "2 0 1" said "header claims 3 vertices and 1 faces, more than a file of 178 bytes can hold".
    const unsigned long long body = text.size() - lines.offset();
    unsigned long long need = 0;
    for (const PlyElement& el : elements)
        need += (ascii ? 2 * el.properties.size() : fixed_item_size(el)) * el.count;
    if (need > body + 1)
        fail(subject, "header claims " + std::to_string(vertex->count) + " vertices and " +
                          std::to_string(face->count) + " faces, more than a file of " +
                          std::to_string(text.size()) + " bytes can hold");
    check_triangle_budget(subject, face->count, options);

    if (ascii) {
        // OpenMesh reads ASCII values with stream extraction, which stops at "nan" or an
        // overflowing number and then silently reads zeros: check the vertex lines. And it reads
        // values, not lines: a stray value on a face line shifted every face after it (exit 0),
        // so each face line must hold its count, that many indices and one value per other
        // property (vertex_indices comes first, checked above).
        for (const PlyElement& el : elements) {
            for (unsigned long long i = 0; i < el.count; ++i) {
                size_t values = 0;
                do {
                    if (!lines.next(line))
                        fail(subject, "file ends after " + std::to_string(i) + " of " +
                                          std::to_string(el.count) + " " + el.name + " lines");
                } while ((values = tokenize(line, tok, 1)) == 0);
                if (&el == face) {
                    long long corners = -1;
                    const size_t others = face->properties.size() - 1;
                    if (e.ply_face_uv_list >= 0)
                        corners = ascii_face_uvs(subject, lines.line(), line, values, *face, i, text, e);
                    else if (!parse_int(tok[0], corners) || corners < 0 ||
                             values != 1 + static_cast<size_t>(corners) + others)
                        fail(subject, line_prefix(lines.line()) + "face line has " + std::to_string(values) +
                                          " values; its count " + shown(tok[0]) + " and " + std::to_string(others) +
                                          " other face propert" + (others == 1 ? "y" : "ies") + " call for " +
                                          (corners < 0 ? string("a whole count first")
                                                       : std::to_string(1 + corners + static_cast<long long>(others))));
                    // Each index a whole number: the reader counted "0x3", "1e1" and "3.9" as
                    // indices and read what it could of them (a face of the wrong vertices, exit 0).
                    size_t pos = 0;
                    for (long long k = 0; k <= corners; ++k) {
                        while (pos < line.size() && is_space(line[pos])) ++pos;
                        const size_t start = pos;
                        while (pos < line.size() && !is_space(line[pos])) ++pos;
                        long long index = -1; // (one past the last vertex: the importer says so)
                        if (k > 0 && (!parse_int(line.substr(start, pos - start), index) || index < 0))
                            fail(subject, line_prefix(lines.line()) + "face index " +
                                              shown(line.substr(start, pos - start)) + " is not a whole number from 0");
                        // Past the vertices, with its line and as written (the reader's 32 bits
                        // wrapped 4294967296 to a face of "out-of-range vertex index -1"; found by
                        // an exploratory session, forty-first).
                        if (k > 0 && static_cast<unsigned long long>(index) >= vertex->count)
                            fail(subject, line_prefix(lines.line()) + "face " + std::to_string(i) + " " +
                                              out_of_range_index(line.substr(start, pos - start), vertex->count));
                    }
                    continue;
                }
                if (&el != vertex) continue;
                // One value per property: the reader reads values, not lines, so a missing one
                // took the next line's first.
                if (values != vertex->properties.size()) {
                    // A face's line where a vertex was due (its count, that many indices and the
                    // face's other values): the header counts more vertices than the file holds
                    // (it said only that the line's values were wrong; found by an exploratory
                    // session, forty-first).
                    long long corners = -1;
                    const bool face_like = face && parse_int(tok[0], corners) && corners >= 3 &&
                                           values == 1 + static_cast<size_t>(corners) + (face->properties.size() - 1);
                    fail(subject, line_prefix(lines.line()) + "vertex line has " + std::to_string(values) +
                                      " values; its " + std::to_string(vertex->properties.size()) +
                                      " properties call for " + std::to_string(vertex->properties.size()) +
                                      (face_like ? " (a face's line, in a vertex's place: the header counts " +
                                                       std::to_string(vertex->count) + " vertices, too many?)"
                                                 : string()));
                }
                size_t pos = 0;
                glm::dvec3 p(0.0);
                for (size_t k = 0; pos < line.size(); ++k) {
                    while (pos < line.size() && is_space(line[pos])) ++pos;
                    if (pos == line.size()) break;
                    const size_t start = pos;
                    while (pos < line.size() && !is_space(line[pos])) ++pos;
                    double value = 0.0;
                    // (Named with its property: a nan normal, which Open3D and others write and
                    // nothing here uses, said only "vertex value 'nan'".)
                    if (!parse_finite_float(line.substr(start, pos - start), &value))
                        fail(subject, line_prefix(lines.line()) + "vertex property '" +
                                          vertex->properties[std::min(k, vertex->properties.size() - 1)].name +
                                          "' is " + shown(line.substr(start, pos - start)) +
                                          ", not a finite number (the reader cannot read past it, used or not)");
                    for (int axis = 0; axis < 3; ++axis)
                        if (k == xyz_at[axis]) p[axis] = value;
                }
                e.positions.push_back(p);
            }
        }
        // The reader stops after the elements the header counts: a face count too small dropped
        // the faces after it, silently (found by an exploratory session). Only white space may follow.
        while (lines.next(line))
            if (tokenize(line, tok, 1) > 0)
                fail(subject, line_prefix(lines.line()) + shown(line) + " follows the elements the header counts (" +
                                  std::to_string(face->count) + " face" + (face->count == 1 ? "" : "s") +
                                  "; is a count too small?)");
    }
    if (!ascii) {
        const string_view data = text.substr(lines.offset());
        const size_t end = binary_ply_end(subject, data, elements, big_endian, vertex->count, e.ply_face_uv_list);
        if (end < data.size() && !std::all_of(data.begin() + std::ptrdiff_t(end), data.end(), is_space))
            fail(subject, "binary PLY has " + std::to_string(data.size() - end) + " bytes after the elements the header "
                          "counts (" + std::to_string(face->count) + " face" + (face->count == 1 ? "" : "s") +
                          "; is a count too small?)");
        e.positions = binary_ply_positions(text.substr(lines.offset()), elements, *vertex, big_endian);
        if (e.ply_face_uv_list >= 0) {
            e.binary_at = lines.offset();
            e.binary_body = binary_ply_without_face_uvs(subject, data, elements, big_endian, e);
        }
        for (const PlyProperty& p : vertex->properties)
            if (p.name == "x" || p.name == "y" || p.name == "z")
                e.positions_from_floats = e.positions_from_floats || (p.type != "double" && p.type != "float64");
    }
    e.binary = !ascii;
    e.add_face_calls = e.file_faces = face->count;
    e.vertices = vertex->count;
    return e;
}

// ---- STL -----------------------------------------------------------------------------------

// An ASCII STL starts with "solid", in either case ("SOLID" from some CAD exporters, whose
// "OUTER" and "VERTEX" OpenMesh's reader reads too).
bool starts_solid(string_view text)
{
    if (text.size() < 5) return false;
    for (size_t i = 0; i < 5; ++i)
        if (std::tolower(static_cast<unsigned char>(text[i])) != "solid"[i]) return false;
    return true;
}

// An STL keyword, in either case.
bool stl_keyword(string_view token, string_view lower)
{
    if (token.size() != lower.size()) return false;
    for (size_t i = 0; i < token.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(token[i])) != lower[i]) return false;
    return true;
}

// ASCII STL's words, with the line each is on (a line ends at LF, CR LF or a CR alone).
class StlWords {
public:
    explicit StlWords(string_view text) : text_(text) {}
    // The next word; false at the file's end.
    bool next(string_view& word, size_t& line)
    {
        while (at_ < text_.size() && is_space(text_[at_])) {
            const char c = text_[at_++];
            line_ += c == '\n' || (c == '\r' && (at_ >= text_.size() || text_[at_] != '\n'));
        }
        if (at_ >= text_.size()) return false;
        from_ = at_;
        while (at_ < text_.size() && !is_space(text_[at_])) ++at_;
        word = text_.substr(from_, at_ - from_);
        line = line_;
        return true;
    }
    // The next word but numbers on line `own` (a vertex's line may hold more than its three, which
    // OpenMesh's reader ignored; a number on a later line is a word of its own: a vertex line
    // that lost its keyword is refused, not dropped; found by a review, thirty-fifth session).
    bool next_after_numbers(string_view& word, size_t& line, size_t own)
    {
        while (next(word, line))
            if (line != own || !parse_finite_float(word)) return true;
        return false;
    }
    void skip_line()
    {
        while (at_ < text_.size() && text_[at_] != '\n' && text_[at_] != '\r') ++at_;
    }
    size_t word_start() const { return from_; } // the last word's
    size_t read() const { return at_; }         // where reading is

private:
    string_view text_;
    size_t at_ = 0, from_ = 0, line_ = 1;
};

// ASCII STL as OpenMesh's reader takes it, in place: "solid", then each facet as "outer" and its
// three "vertex x y z" lines (the reader wants no more: it ignores every line without "outer").
// The facets have been checked (scan_stl). Each facet's lines are shorter than the words they come
// from ("outer loop", "vertex", three numbers each, "endfacet": 49 bytes and the numbers at the
// least, against 36 and the numbers), so the text written stays behind the text read.
void rewrite_ascii_stl(string& text)
{
    StlWords words(text);
    size_t w = 0;
    const auto put = [&](string_view piece) {
        std::memmove(text.data() + w, piece.data(), piece.size());
        w += piece.size();
    };
    string facet; // one facet's lines, put once it is read whole
    string_view word;
    size_t line = 0;
    bool first = true;
    while (words.next(word, line)) {
        if (stl_keyword(word, "solid") || stl_keyword(word, "endsolid")) {
            words.skip_line();
            if (first) put("solid\n"); // (the file's first word: six bytes at most past its start)
            first = false;
            continue;
        }
        first = false;
        if (!stl_keyword(word, "outer")) continue;
        words.next(word, line); // loop
        facet = "outer\n";
        size_t vertex_line = 0;
        for (int k = 0; k < 3; ++k) {
            if (k == 0) words.next(word, line); // vertex
            else words.next_after_numbers(word, line, vertex_line); // (past more numbers on the last vertex's line)
            facet += "vertex";
            for (int c = 0; c < 3; ++c) {
                words.next(word, line);
                facet += ' ';
                facet += word;
            }
            vertex_line = line; // (as the scan: the last number's line)
            facet += '\n';
        }
        words.next_after_numbers(word, line, vertex_line); // endloop or endfacet
        if (stl_keyword(word, "endloop")) words.next(word, line); // endfacet
        put(facet);
    }
    text.resize(w);
}

Expect scan_stl(const string& subject, string_view text, const MeshOptions& options)
{
    Expect e;
    e.faces_may_collapse = true;
    // Binary when the size matches the triangle count in the header (what OpenMesh checks too);
    // otherwise it must be ASCII, starting with "solid".
    if (text.size() >= 84) {
        std::uint32_t nt = 0;
        std::memcpy(&nt, text.data() + 80, 4);
        if (84ull + 50ull * nt == text.size()) {
            check_triangle_budget(subject, nt, options);
            // NaN keys would break the ordered map OpenMesh merges STL vertices with.
            for (std::uint32_t t = 0; t < nt; ++t) {
                float v[9];
                std::memcpy(v, text.data() + 84 + size_t(t) * 50 + 12, sizeof v);
                for (float x : v)
                    if (!std::isfinite(x))
                        fail(subject, "triangle " + std::to_string(t) +
                                          " has a coordinate that is not a finite number");
            }
            e.binary = true;
            e.file_faces = nt;
            return e;
        }
    }
    size_t first = 0;
    while (first < text.size() && is_space(text[first])) ++first;
    if (!starts_solid(text.substr(first))) {
        string problem = "is neither ASCII STL (it does not start with 'solid')";
        if (text.size() >= 84) {
            std::uint32_t nt = 0;
            std::memcpy(&nt, text.data() + 80, 4);
            problem += " nor binary STL (its header claims " + std::to_string(nt) + " triangles, " +
                       std::to_string(84ull + 50ull * nt) + " bytes, but the file has " +
                       std::to_string(text.size()) + ")";
        } else {
            problem += " nor binary STL (shorter than a binary header)";
        }
        fail(subject, problem);
    }
    // Read word by word, as the format is (white space of any kind between words, keywords in
    // either case), and handed to OpenMesh rewritten one keyword a line (rewrite_ascii_stl): its
    // reader takes any line holding "outer" for a facet's start and the next three lines for its
    // vertices, so a blank line among them, a facet on one line or "Outer Loop" refused valid
    // files (found by an exploratory session, thirty-fifth), and `solid Router_bracket` read the
    // lines after the name as vertices. Names (the rest of a "solid" or "endsolid" line) are left
    // out; words outside facets but "vertex" are skipped, as the reader skips them.
    StlWords words(text);
    bool solid_ended = false; // "endsolid" after the last facet
    size_t after_end_line = 0; // the first line with words after an "endsolid" and before a "solid"
    string_view after_end;
    string_view word;
    size_t word_line = 0;
    while (words.next(word, word_line)) {
        if (stl_keyword(word, "solid") || stl_keyword(word, "endsolid")) {
            solid_ended = stl_keyword(word, "endsolid");
            const size_t name_at = words.read();
            words.skip_line(); // (its name)
            // Facets on the "solid" line (a file on one line) are its name, as the reader takes
            // it: the file said "contains no faces" (found by an exploratory session, fifty-first).
            if (!solid_ended) {
                string_view name[64];
                const size_t n = tokenize(text.substr(name_at, words.read() - name_at), name, 64);
                for (size_t i = 0; i + 1 < std::min<size_t>(n, 64); ++i)
                    if (stl_keyword(name[i], "outer") && stl_keyword(name[i + 1], "loop"))
                        fail(subject, line_prefix(word_line) + "facets on the 'solid' line, whose rest is the solid's "
                                                               "name: each facet must start on a line of its own");
            }
            continue;
        }
        // Words after an "endsolid" that no "solid" follows are in no solid: skipped, as
        // OpenMesh skips them, but said (they went without a word; found by an exploratory
        // session, forty-ninth).
        if (solid_ended && after_end_line == 0) {
            after_end_line = word_line;
            after_end = word;
        }
        // A fourth vertex (or more) in a facet, or one outside a facet.
        if (stl_keyword(word, "vertex"))
            fail(subject, line_prefix(word_line) + "a vertex beyond the three after 'outer loop' (STL facets are triangles)");
        if (!stl_keyword(word, "outer")) continue;
        const size_t outer_line = word_line;
        if (!words.next(word, word_line)) fail(subject, "file ends inside a facet");
        if (!stl_keyword(word, "loop"))
            fail(subject, line_prefix(word_line) + "expected 'loop' after 'outer' (line " + std::to_string(outer_line) +
                              "), found " + shown(word));
        size_t vertex_line = 0;
        for (int k = 0; k < 3; ++k) {
            string_view v;
            size_t l = 0;
            if (!(k == 0 ? words.next(v, l) : words.next_after_numbers(v, l, vertex_line)))
                fail(subject, "file ends inside a facet");
            vertex_line = l;
            // (A facet's end after fewer than three vertices said so: it read "expected 'vertex x
            // y z' with finite numbers" on the endloop line; an exploratory session, forty-ninth.)
            if (k > 0 && (stl_keyword(v, "endloop") || stl_keyword(v, "endfacet")))
                fail(subject, line_prefix(vertex_line) + shown(v) + " after " + std::to_string(k) +
                                  (k == 1 ? " vertex" : " vertices") + " (STL facets are triangles: three)");
            if (!stl_keyword(v, "vertex")) fail(subject, line_prefix(vertex_line) + "expected 'vertex x y z' with finite numbers");
            for (int c = 0; c < 3; ++c)
                if (!words.next(v, l) || !parse_finite_float(v))
                    fail(subject, line_prefix(vertex_line) + "expected 'vertex x y z' with finite numbers");
            vertex_line = l; // (its last number's: more on that line are ignored)
        }
        // After the third vertex (and any more numbers on its line, which the reader ignored):
        // "endloop", then "endfacet" (a file cut inside a facet after its third vertex was read
        // without a word, the facet and the rest of the file gone; found by an exploratory
        // session, thirty-third). A facet without "endloop" but with its "endfacet" is taken, as
        // OpenMesh's reader takes it.
        if (!words.next_after_numbers(word, word_line, vertex_line)) fail(subject, "file ends inside a facet (no 'endloop')");
        if (stl_keyword(word, "endloop") && !words.next(word, word_line))
            fail(subject, "file ends inside a facet (no 'endfacet')");
        if (!stl_keyword(word, "endfacet")) {
            if (stl_keyword(word, "vertex"))
                fail(subject, line_prefix(word_line) + "a vertex beyond the three after 'outer loop' (STL facets are triangles)");
            const auto cut_from = [&](string_view full) {
                return word.size() < full.size() && stl_keyword(word, full.substr(0, word.size()));
            };
            fail(subject, line_prefix(word_line) + "expected 'endfacet', found " + shown(word) +
                              (cut_from("endloop") || cut_from("endfacet") ? " (the file is cut short?)" : ""));
        }
        // (As they come: no more read past the limit, whose count is then a lower bound.)
        if (++e.file_faces > options.max_triangles)
            fail(subject, "has more than " + std::to_string(options.max_triangles) +
                              " triangles (facets); the limit is " + std::to_string(options.max_triangles));
        solid_ended = false;
    }
    e.stl_ascii = true;
    if (after_end_line != 0)
        warn(subject + ": " + line_prefix(after_end_line) + shown(after_end) +
             " comes after an 'endsolid', outside any solid: the words there are ignored");
    // A file cut between two facets reads without a fault but the facets after the cut: the
    // last solid's "endsolid" is the one sign of its end.
    if (e.file_faces > 0 && !solid_ended)
        warn(subject + ": no 'endsolid' after its last facet: the file may be cut short (" +
             std::to_string(e.file_faces) + " facet" + (e.file_faces == 1 ? "" : "s") + " read)");
    // A binary STL whose header starts with "solid" (as some exporters write) but whose size does
    // not match its count, cut short or padded: said "contains no faces".
    if (e.file_faces == 0 && text.size() >= 84 && text.find('\0') != string_view::npos) {
        std::uint32_t nt = 0;
        std::memcpy(&nt, text.data() + 80, 4);
        fail(subject, "starts with 'solid' but holds binary data: a binary STL whose header claims " + std::to_string(nt) +
                          " triangles (" + std::to_string(84ull + 50ull * nt) + " bytes), but the file has " +
                          std::to_string(text.size()));
    }
    check_triangle_budget(subject, e.file_faces, options);
    return e;
}

// The scan's rewrites of `text` for OpenMesh at the offsets it found them, so before any rewrite
// that moves bytes: each of Expect::blanks made spaces, and the binary body replaced.
void rewrite_for_reader(string& text, Expect& e)
{
    for (const auto& [at, length] : e.blanks) text.replace(at, length, length, ' ');
    if (!e.binary_body.empty()) text.replace(e.binary_at, string::npos, e.binary_body);
    e.binary_body = {};
}

// ---- the importer ---------------------------------------------------------------------------

// Receives what an OpenMesh reader parses and keeps it as a polygon soup. Invalid faces are not
// stored; the first one is remembered for the error message.
class SoupImporter final : public omio::BaseImporter {
public:
    SoupImporter(RawMesh& mesh, const Expect& expect) : m_(mesh), expect_(expect) {}

    size_t add_face_calls = 0;
    long long first_bad_face = -1;
    string bad_problem;
    bool any_vertex_uv = false;
    std::vector<glm::vec2> vertex_uv;
    std::vector<std::uint8_t> vertex_has_uv;

    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override
    {
        m_.positions.emplace_back(p[0], p[1], p[2]);
        return OpenMesh::VertexHandle(int(m_.positions.size() - 1));
    }
    OpenMesh::VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3f(0.0f)); }
    void set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& p) override
    {
        if (valid(vh)) m_.positions[size_t(vh.idx())] = glm::vec3(p[0], p[1], p[2]);
    }

    OpenMesh::FaceHandle add_face(const VHandles& handles) override
    {
        const size_t face_number = add_face_calls++;
        if (first_bad_face >= 0) return OpenMesh::FaceHandle();
        const size_t k = next_repeating_;
        if (k < expect_.repeating_calls.size() && expect_.repeating_calls[k] == face_number) {
            VHandles all;
            for (size_t c = expect_.repeating_offsets[k]; c < expect_.repeating_offsets[k + 1]; ++c)
                all.emplace_back(int(expect_.repeating_corners[c]));
            ++next_repeating_;
            return store_face(face_number, all);
        }
        return store_face(face_number, handles);
    }
    OpenMesh::FaceHandle store_face(size_t face_number, const VHandles& handles)
    {
        if (handles.size() < 3) return bad(face_number, "has fewer than 3 vertices");
        for (const OpenMesh::VertexHandle& vh : handles) {
            if (!valid(vh))
                return bad(face_number, out_of_range_index(std::to_string(vh.idx()), m_.positions.size()));
        }
        if (m_.corners.size() + handles.size() > std::numeric_limits<std::uint32_t>::max())
            return bad(face_number, "exceeds the supported number of corners");
        for (const OpenMesh::VertexHandle& vh : handles)
            m_.corners.push_back(std::uint32_t(vh.idx()));
        m_.face_offsets.push_back(std::uint32_t(m_.corners.size()));
        m_.corner_uvs.resize(m_.corners.size(), glm::vec2(0.0f));
        m_.face_has_uv.push_back(0);
        return OpenMesh::FaceHandle(int(m_.face_count() - 1));
    }

    // OBJ: per-corner texture coordinates, starting at the corner of vertex `vh` (ImporterT's
    // convention) and following the face's corner order.
    void add_face_texcoords(OpenMesh::FaceHandle fh, OpenMesh::VertexHandle vh,
                            const std::vector<OpenMesh::Vec2f>& uvs) override
    {
        if (!fh.is_valid() || size_t(fh.idx()) >= m_.face_count() || uvs.empty()) return;
        m_.file_had_uvs = true;
        const size_t f = size_t(fh.idx());
        const size_t begin = m_.face_offsets[f];
        const size_t n = m_.face_offsets[f + 1] - begin;
        if (uvs.size() != n) {
            // OpenMesh dropped repeated corners or an unreadable texture index: the UVs can no
            // longer be matched to corners, so this face gets generated ones.
            return;
        }
        size_t start = 0;
        while (start < n && m_.corners[begin + start] != std::uint32_t(vh.idx())) ++start;
        if (start == n) start = 0;
        for (size_t i = 0; i < n; ++i) {
            const OpenMesh::Vec2f& t = uvs[i];
            m_.corner_uvs[begin + (start + i) % n] = glm::vec2(t[0], t[1]);
        }
        m_.face_has_uv[f] = 1;
    }
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec3f>&) override
    {
    }

    // PLY and OFF: per-vertex texture coordinates.
    void set_texcoord(OpenMesh::VertexHandle vh, const OpenMesh::Vec2f& t) override
    {
        if (!valid(vh)) return;
        if (vertex_uv.size() < m_.positions.size()) {
            vertex_uv.resize(m_.positions.size(), glm::vec2(0.0f));
            vertex_has_uv.resize(m_.positions.size(), 0);
        }
        vertex_uv[size_t(vh.idx())] = glm::vec2(t[0], t[1]);
        vertex_has_uv[size_t(vh.idx())] = 1;
        any_vertex_uv = true;
        m_.file_had_uvs = true;
    }
    void set_texcoord(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& t) override
    {
        set_texcoord(vh, OpenMesh::Vec2f(t[0], t[1]));
    }

    void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override
    {
        m_.had_normals = true;
    }
    void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override
    {
        m_.had_normals = true;
    }

    // Everything else a reader may deliver is not used.
    OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override
    {
        return OpenMesh::HalfedgeHandle();
    }
    OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override
    {
        return OpenMesh::FaceHandle();
    }
    void set_face_texindex(OpenMesh::FaceHandle, int) override {}
    void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f&) override {}
    void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
    void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {}
    void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {}
    void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
    void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f&) override {}
    void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}
    // Header counts are validated against the file size before reading, but vectors still grow
    // on demand rather than trusting them.
    void reserve(unsigned int, unsigned int, unsigned int) override {}
    size_t n_vertices() const override { return m_.positions.size(); }
    size_t n_faces() const override { return m_.face_count(); }
    size_t n_edges() const override { return 0; }

private:
    bool valid(OpenMesh::VertexHandle vh) const
    {
        return vh.idx() >= 0 && size_t(vh.idx()) < m_.positions.size();
    }
    OpenMesh::FaceHandle bad(size_t face_number, string problem)
    {
        first_bad_face = static_cast<long long>(face_number);
        bad_problem = std::move(problem);
        return OpenMesh::FaceHandle();
    }

    RawMesh& m_;
    const Expect& expect_;
    size_t next_repeating_ = 0;
};

string lower(string s)
{
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// How many bytes a mesh file within `options.max_triangles` may take, so that a huge file is
// refused by its size and a pipe stops being read there. ASCII STL is the most verbose format
// per triangle: a facet normal, three vertex lines and five keywords, about 250 bytes with
// %e floats (OBJ with v, vt and vn takes about 100, binary PLY with doubles less); 512 bytes
// leaves room for more digits and indentation. At least 64 MiB, for comments and small limits.
// The default 10,000,000 triangles give 4.8 GiB; the mesh built from them takes 3 GB or more.
std::uint64_t max_mesh_file_bytes(const MeshOptions& options)
{
    constexpr std::uint64_t kBytesPerTriangle = 512, kFloor = std::uint64_t(64) << 20;
    const std::uint64_t triangles = options.max_triangles;
    if (triangles > (std::numeric_limits<std::uint64_t>::max() - kFloor) / kBytesPerTriangle)
        return std::numeric_limits<std::uint64_t>::max() - 1;
    return std::max(kFloor, triangles * kBytesPerTriangle);
}

string read_whole_file(const fs::path& path, const string& subject, const MeshOptions& options)
{
    std::error_code ec;
    if (!fs::exists(path, ec)) {
        // (A loop of links, or one whose target is missing, said "does not exist" of the name
        // given, which is there.)
        if (ec == std::errc::too_many_symbolic_link_levels) fail(subject, "is a loop of symbolic links");
        if (const string link = broken_link_reason(path.string()); !link.empty()) fail(subject, link);
        fail(subject, "does not exist");
    }
    return read_input_text(
        path.string(),
        {max_mesh_file_bytes(options), "a mesh file",
         "the most a mesh within the limit of " + std::to_string(options.max_triangles) +
             " triangles can take (512 bytes a triangle, and at least 64 MiB)"});
}

// A read-only, seekable stream over bytes already in memory, without a copy (the OBJ reader
// reads its input twice, seeking back to the start in between).
class MemoryBuffer : public std::streambuf {
public:
    explicit MemoryBuffer(string_view bytes)
    {
        char* p = const_cast<char*>(bytes.data()); // never written: no put area, no pbackfail
        setg(p, p, p + bytes.size());
    }

protected:
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override
    {
        if (!(which & std::ios_base::in)) return pos_type(off_type(-1));
        const off_type base = dir == std::ios_base::beg   ? 0
                              : dir == std::ios_base::cur ? gptr() - eback()
                                                          : egptr() - eback();
        const off_type to = base + off;
        if (to < 0 || to > egptr() - eback()) return pos_type(off_type(-1));
        setg(eback(), eback() + to, egptr());
        return pos_type(to);
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override
    {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }
};

// A comment may follow a line's values ("f 1 2 3 4 # quad"): it read as a malformed face corner
// '#', and OpenMesh's reader takes no trailing comments either. Blanked (spaces, the same length,
// so line numbers and offsets stay) before either reads the text.
void blank_obj_comments(string& text)
{
    bool comment = false;
    for (char& c : text) {
        if (c == '\n') comment = false;
        else if (c == '#') comment = true;
        if (comment && c != '\r') c = ' ';
    }
}

// Geomview's OFF allows comments, from '#' to the line's end, anywhere: OpenMesh's reader takes
// none (a comment line was read as values), and the scan refused them with messages that blamed
// something else ("the counts must be on the line after 'OFF'" for `OFF # cube`, "vertex
// position is not three finite numbers" for a comment line among the vertices; found by an
// exploratory session, thirty-third). Taken out, with the white space before them, before either
// reads the text; the line breaks stay, so every line keeps its number. In a binary OFF only the
// header line's (the data after it is not text).
void strip_off_comments(string& text)
{
    if (text.find('#') == string::npos) return;
    string out;
    out.reserve(text.size());
    bool first_line = true;
    for (size_t i = 0; i < text.size();) {
        size_t end = text.find('\n', i);
        end = end == string::npos ? text.size() : end + 1;
        string_view line(text.data() + i, end - i);
        size_t keep = line.size();
        if (const size_t hash = line.find('#'); hash != string_view::npos) {
            size_t eol = line.size();
            while (eol > hash && (line[eol - 1] == '\n' || line[eol - 1] == '\r')) --eol;
            keep = hash;
            while (keep > 0 && (line[keep - 1] == ' ' || line[keep - 1] == '\t')) --keep;
            out.append(line.substr(0, keep)).append(line.substr(eol));
        } else {
            out.append(line);
        }
        i = end;
        if (first_line) {
            first_line = false;
            string_view tok[2];
            if (tokenize(out, tok, 2) == 2 && tok[1] == "BINARY") {
                out.append(text, i, string::npos);
                break;
            }
        }
    }
    text = std::move(out);
}

// A backslash at the end of a line continues it on the next ("f 1 2 \\" then "3 4"); neither
// the scan nor OpenMesh's reader joins such lines. The joined line keeps the text's length and
// every later line its number: each backslash and line break become a space, and the line breaks
// follow the joined line (errors in it name its first line).
void join_obj_continuations(string& text)
{
    if (text.find('\\') == string::npos) return;
    string out;
    out.reserve(text.size());
    size_t pending = 0; // line breaks taken out of the current line
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\\') {
            size_t j = i + 1;
            if (j < text.size() && text[j] == '\r') ++j;
            if (j < text.size() && text[j] == '\n') {
                out.append(j - i, ' ');
                ++pending;
                i = j;
                continue;
            }
        }
        out.push_back(c);
        if (c == '\n') {
            out.append(pending, '\n');
            pending = 0;
        }
    }
    out.append(pending, '\n');
    text = std::move(out);
}

// Materials are not used (docs/mesh-input.md), but OpenMesh's OBJ reader opens the file an
// `mtllib` line names and reads it to its end: a FIFO there hung it, /dev/zero filled memory.
// Such lines become comments ('m' -> '#', the same length) in the bytes OpenMesh parses; the
// test is OpenMesh's own (the first word of the line, trimmed of " \t\r", is "mtllib").
void drop_obj_material_libraries(string& text)
{
    static constexpr string_view kKey = "mtllib";
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == string::npos) end = text.size();
        size_t i = pos;
        while (i < end && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
        if (end - i >= kKey.size() && string_view(text).substr(i, kKey.size()) == kKey &&
            (i + kKey.size() == end || is_space(text[i + kKey.size()])))
            text[i] = '#';
        pos = end + 1;
    }
}

// OpenMesh's OFF reader learns a file's variant (ST, C, N, BINARY: how many numbers a vertex
// has) only in can_u_read(filename), which reads the first line of the file it names; its stream
// read then uses what the latest such call found. So that first line is handed to it in an
// anonymous in-memory file (memfd), named through /proc/self/fd. The NUL and ".off" after the
// number are for OpenMesh's extension check, which looks at the whole std::string, while the
// open() underneath sees only the C string before the NUL. Where that is not possible (no /proc),
// a regular file is asked by its own name, as OpenMesh's IOManager did (it is not a pipe, so it
// can be opened again and read a second time without waiting).
// Returns OpenMesh's answer (false: it refuses the header, as it would the file), or nothing
// where the line could not be handed over.
std::optional<bool> prime_off_reader(string_view text, const fs::path& path)
{
    const size_t newline = text.find('\n');
    const string_view header = newline == string_view::npos ? text : text.substr(0, newline + 1);
    const int fd = ::memfd_create("prismrelief-off-header", MFD_CLOEXEC);
    if (fd >= 0) {
        std::optional<bool> answer;
        string name = "/proc/self/fd/" + std::to_string(fd);
        if (::write(fd, header.data(), header.size()) == static_cast<ssize_t>(header.size()) &&
            ::access(name.c_str(), R_OK) == 0) {
            name.push_back('\0');
            name += ".off";
            answer = omio::OFFReader().can_u_read(name);
        }
        ::close(fd);
        if (answer) return answer;
    }
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode))
        return omio::OFFReader().can_u_read(path.string());
    return std::nullopt;
}

} // namespace

// A mesh far from its file's origin (geographic coordinates: a 3-unit torus at 5e6) is kept
// relative to its box's centre, taken in double from the positions the scan read (`precise`, in
// the reader's order). From float positions 0.5 apart a torus there lost half its triangles as
// degenerate, and drew with IoU 0.77. Where the scan read none (binary STL and OFF, ASCII STL)
// the reader's floats are all there is: they are recentred too, exactly, so that the mesh is
// drawn as its file has it rather than with the rounding of its floats' sum with the far
// translation once more. Only a mesh whose centre has a coordinate more than 4 times its box's
// longest side: every other keeps the reader's floats as they are, to the bit. The box is the
// faces' corners' (an unused vertex at the file's origin, a marker, kept the torus from being
// recentred).
void recentre(RawMesh& mesh, std::vector<glm::dvec3> precise, bool from_floats)
{
    mesh.float_positions = from_floats || precise.size() != mesh.positions.size();
    if (mesh.float_positions) precise.assign(mesh.positions.begin(), mesh.positions.end());
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (const std::uint32_t v : mesh.corners) {
        lo = glm::min(lo, precise[v]);
        hi = glm::max(hi, precise[v]);
    }
    if (!(lo.x <= hi.x)) return; // no corners
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const double far = std::max({std::abs(centre.x), std::abs(centre.y), std::abs(centre.z)});
    if (!(far > 4.0 * extent)) return;
    mesh.origin = centre;
    for (size_t i = 0; i < precise.size(); ++i) mesh.positions[i] = glm::vec3(precise[i] - centre);
}

RawMesh read_raw_mesh(const fs::path& path, const MeshOptions& options)
{
    const string subject = path.string();
    const string ext = lower(path.extension().string());
    // A folder is said as such whatever its name (one without an extension was "unknown mesh
    // format (no extension)"; found by an exploratory session, forty-first).
    std::error_code ec;
    if (fs::is_directory(path, ec)) fail(subject, "is a folder, not a mesh file");
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
        fail(subject, "unknown mesh format " +
                          (ext.empty() ? string("(no extension)") : shown(ext)) +
                          "; supported: .obj .off .ply .stl");

    string text = read_whole_file(path, subject, options);
    if (text.empty()) fail(subject, "is empty");
    // A UTF-8 byte-order mark (some Windows editors write one) is not part of any format: each
    // reader stumbled on it ("does not start with 'ply'", "unsupported OFF variant", a vertex
    // count one short). Not before a binary STL's header unless "solid" follows (ASCII).
    static constexpr string_view kBom = "\xEF\xBB\xBF";
    if (string_view(text).substr(0, 3) == kBom &&
        (ext != ".stl" || starts_solid(string_view(text).substr(3))))
        text.erase(0, 3);

    // UTF-16 text (Windows tools write it, with its byte-order mark): every other byte is NUL.
    if (ext != ".stl") {
        const string_view head = string_view(text).substr(0, 2);
        // Without the mark: a NUL second (little-endian), or first in ASCII text's pairs
        // (big-endian, which was read as another kind of file; found by an exploratory session,
        // fifty-first).
        const auto big_endian_ascii = [&] {
            const size_t pairs = std::min<size_t>(text.size() / 2, 32);
            for (size_t i = 0; i < pairs; ++i) {
                const unsigned char c = static_cast<unsigned char>(text[2 * i + 1]);
                if (text[2 * i] != '\0' || !(c == '\t' || c == '\n' || c == '\r' || (c >= 0x20 && c < 0x7f)))
                    return false;
            }
            return pairs > 0;
        };
        if (head == "\xFF\xFE" || head == "\xFE\xFF" || (text.size() >= 2 && text[0] != '\0' && text[1] == '\0') ||
            big_endian_ascii())
            fail(subject, "is UTF-16 text; the reader takes ASCII or UTF-8: save it as UTF-8");
    }
    Expect expect;
    omio::Options requested = omio::Options::VertexNormal;
    if (ext == ".obj") {
        // OBJ is text: a NUL byte in its first kilobyte is another kind of file under the name
        // (a PNG renamed .obj said "contains no faces"; found by an exploratory session,
        // thirty-third).
        if (string_view(text).substr(0, 1024).find('\0') != string_view::npos)
            fail(subject, "holds binary data, not OBJ text (another kind of file named .obj?)");
        blank_obj_comments(text);
        join_obj_continuations(text);
        expect = scan_obj(subject, text, options);
        // OBJ texture coordinates belong to face corners; per-vertex ones would lose seams.
        requested += omio::Options::FaceTexCoord;
    } else if (ext == ".off") {
        refuse_cr_line_ends(subject, text); // (first: with no line ends a comment would run to the file's end)
        strip_off_comments(text);
        // White space before the header's keyword: OpenMesh's reader looks for it at the line's
        // start ("the reader reported a failure"; found by an exploratory session, fifty-first).
        text.erase(0, std::min(text.find_first_not_of(" \t\f\v"), text.size()));
        expect = scan_off(subject, text, options);
        rewrite_for_reader(text, expect); // (before off_counts_end's insert)
        requested += omio::Options::VertexTexCoord;
    } else if (ext == ".ply") {
        expect = scan_ply(subject, text, options);
        rewrite_for_reader(text, expect); // (before the header's rewrite)
        normalize_ply_header(text, expect.ply_unread_uv, expect.ply_texture_uv,
                             expect.ply_face_uv_list >= 0); // (after the scan: its line numbers)
        requested += omio::Options::VertexTexCoord;
    } else {
        expect = scan_stl(subject, text, options);
    }
    if (expect.file_faces == 0) fail(subject, "contains no faces");

    if (ext == ".obj") drop_obj_material_libraries(text); // after the scan: its line numbers
    if (expect.stl_ascii) rewrite_ascii_stl(text);
    if (expect.off_counts_end != string_view::npos) text.insert(expect.off_counts_end, " 0");
    if (expect.off_single_spaces) {
        size_t out = 0;
        for (size_t i = 0; i < text.size(); ++i) {
            const char c = text[i] == '\t' ? ' ' : text[i];
            if (c == ' ' && out > 0 && text[out - 1] == ' ') continue;
            text[out++] = c;
        }
        text.resize(out);
    }
    RawMesh mesh;
    SoupImporter importer(mesh, expect);
    bool ok = false;
    bool handed = true; // false: OpenMesh's OFF reader could not be given the header line
    {
        // Reader modules are global singletons with per-read state: one read at a time.
        static std::mutex openmesh_mutex;
        std::lock_guard lock(openmesh_mutex);
        QuietOpenMesh quiet;
        try {
            MemoryBuffer buffer(text);
            std::istream stream(&buffer);
            omio::Options opt = requested;
            if (ext == ".obj") {
                ok = omio::OBJReader().read(stream, importer, opt);
            } else if (ext == ".off") {
                const std::optional<bool> primed = prime_off_reader(text, path);
                handed = primed.has_value();
                ok = primed.value_or(false) && omio::OFFReader().read(stream, importer, opt);
            } else if (ext == ".ply") {
                ok = omio::PLYReader().read(stream, importer, opt);
            } else {
                // The STL type was decided above; the stream interface takes it as an option, so
                // OpenMesh's own guess cannot differ from the validation.
                if (expect.binary) opt += omio::Options::Binary;
                ok = omio::STLReader().read(stream, importer, opt);
            }
        } catch (const std::bad_alloc&) {
            fail(subject, "not enough memory to read it");
        } catch (const std::exception& e) {
            fail(subject, string("could not be read: ") + e.what());
        }
    }
    if (!handed)
        fail(subject, "could not be read as off (OpenMesh's reader could not be given its header "
                      "line: is /proc mounted?)");
    if (!ok)
        fail(subject, "could not be read as " + ext.substr(1) + " (the reader reported a failure)");

    // (A binary PLY's face of fewer than 3 vertices is refused by its scan, which tells a header
    // that counts more vertices than the body holds: short_binary_ply_face.)
    if (importer.first_bad_face >= 0)
        fail(subject, "face " + std::to_string(importer.first_bad_face) + " " + importer.bad_problem);
    if (expect.vertices != 0 && mesh.positions.size() != expect.vertices)
        fail(subject, std::to_string(mesh.positions.size()) + " of " +
                          std::to_string(expect.vertices) + " vertices could be read");
    if (expect.faces_may_collapse) {
        mesh.collapsed_faces =
            expect.file_faces - std::min(expect.file_faces, importer.add_face_calls);
    } else {
        if (importer.add_face_calls != expect.add_face_calls)
            fail(subject, std::to_string(expect.add_face_calls -
                                         std::min(expect.add_face_calls, importer.add_face_calls)) +
                              " of " + std::to_string(expect.file_faces) +
                              " faces could not be read");
        mesh.collapsed_faces = expect.file_faces - expect.add_face_calls;
    }
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::vec3& p = mesh.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            fail(subject,
                 "vertex " + std::to_string(i) + " has a coordinate that is not a finite number");
    }
    // A binary file's values as the scan read them must be what OpenMesh read, rounded to floats
    // (each found the body on its own): else the reader's floats are used.
    if (expect.binary && expect.positions.size() == mesh.positions.size())
        for (size_t i = 0; i < mesh.positions.size(); ++i)
            if (glm::vec3(expect.positions[i]) != mesh.positions[i]) {
                expect.positions.clear();
                break;
            }
    recentre(mesh, std::move(expect.positions), expect.positions_from_floats);
    if (mesh.face_count() == 0)
        fail(subject, mesh.collapsed_faces > 0 ? "all " + std::to_string(mesh.collapsed_faces) +
                                                     " faces are degenerate (repeated vertices)"
                                               : string("contains no faces"));

    // A PLY's texcoord lists: each face's corners in the file's order (the importer stores every
    // face the reader hands it, in order, or the read fails), over per-vertex ones.
    if (!expect.ply_face_uvs.empty() && expect.ply_face_uvs.size() == mesh.corners.size()) {
        std::copy(expect.ply_face_uvs.begin(), expect.ply_face_uvs.end(), mesh.corner_uvs.begin());
        std::fill(mesh.face_has_uv.begin(), mesh.face_has_uv.end(), std::uint8_t(1));
        mesh.file_had_uvs = true;
    }
    // Per-vertex texture coordinates (PLY, STOFF) become corner UVs of faces whose vertices all
    // have one.
    if (importer.any_vertex_uv) {
        importer.vertex_has_uv.resize(mesh.positions.size(), 0);
        importer.vertex_uv.resize(mesh.positions.size(), glm::vec2(0.0f));
        for (size_t f = 0; f < mesh.face_count(); ++f) {
            if (mesh.face_has_uv[f]) continue;
            bool all = true;
            for (size_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c)
                all = all && importer.vertex_has_uv[mesh.corners[c]];
            if (!all) continue;
            for (size_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c)
                mesh.corner_uvs[c] = importer.vertex_uv[mesh.corners[c]];
            mesh.face_has_uv[f] = 1;
        }
    }
    bool any_uv = false;
    for (const glm::vec2& uv : mesh.corner_uvs) {
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
            fail(subject, "a texture coordinate is not a finite number");
    }
    for (std::uint8_t h : mesh.face_has_uv) any_uv = any_uv || h;
    if (!any_uv) {
        mesh.corner_uvs.clear();
        mesh.face_has_uv.clear();
    }
    return mesh;
}

} // namespace pr
