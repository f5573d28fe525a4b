#include "io/obj_mesh.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>
#include <utility>

#include "core/error.hpp"

namespace sph {

double TriangleMesh::volume() const {
    if (vertices.empty()) return 0.0;
    // Tetrahedra against the first vertex rather than the origin: the same total for a
    // closed mesh, with less cancellation when the mesh sits far from the origin.
    const Vec3d c = vertices[0];
    double sum = 0.0;
    for (const auto& t : triangles) {
        const Vec3d& a = vertices[t[0]];
        const Vec3d& b = vertices[t[1]];
        const Vec3d& d = vertices[t[2]];
        const double ax = a.x - c.x, ay = a.y - c.y, az = a.z - c.z;
        const double bx = b.x - c.x, by = b.y - c.y, bz = b.z - c.z;
        const double dx = d.x - c.x, dy = d.y - c.y, dz = d.z - c.z;
        sum += ax * (by * dz - bz * dy) + ay * (bz * dx - bx * dz) + az * (bx * dy - by * dx);
    }
    return std::abs(sum) / 6.0;
}

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw InputError("Mesh file '" + path + "' " + what);
}

[[noreturn]] void fail_line(const std::string& path, long line, const std::string& what) {
    throw InputError("Mesh file '" + path + "' line " + std::to_string(line) + ": " + what);
}

// The whole file in one buffer: parsing a buffer is several times faster than streams.
std::string read_whole_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        fail(path, "cannot be read: it is a directory.");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) fail(path, std::string("cannot be opened: ") + std::strerror(errno) + ".");
    std::string buf;
    char chunk[1 << 16];
    size_t n;
    while ((n = std::fread(chunk, 1, sizeof chunk, f.get())) > 0) buf.append(chunk, n);
    if (std::ferror(f.get())) fail(path, "cannot be read (I/O error).");
    return buf;
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

inline const char* skip_space(const char* p, const char* end) {
    while (p < end && is_space(*p)) ++p;
    return p;
}

// One number from [p, end); false if there is none. Infinities and NaNs parse (and are
// rejected by the caller with a clearer message); out-of-range values become infinities.
bool parse_double(const char*& p, const char* end, double& out) {
    p = skip_space(p, end);
    if (p < end && *p == '+') ++p;  // from_chars refuses a leading '+', OBJ writers emit it
    const auto r = std::from_chars(p, end, out);
    if (r.ec == std::errc::result_out_of_range) {
        out = HUGE_VAL;
    } else if (r.ec != std::errc()) {
        return false;
    }
    p = r.ptr;
    return p == end || is_space(*p);
}

struct ForwardRef {
    long line;
    int index;
};

}  // namespace

TriangleMesh read_obj(const std::string& path, MeshCheck check) {
    const std::string buf = read_whole_file(path);
    TriangleMesh mesh;
    mesh.vertices.reserve(buf.size() / 64);
    mesh.triangles.reserve(buf.size() / 32);
    std::vector<int> poly;                // indices of the face being read
    std::vector<ForwardRef> forward;      // indices past the vertices read so far
    long faces = 0;

    const char* p = buf.data();
    const char* const end = p + buf.size();
    for (long line = 1; p < end; ++line) {
        const char* eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
        if (!eol) eol = end;
        const char* q = skip_space(p, eol);
        const char* next = eol < end ? eol + 1 : end;

        if (eol - q >= 2 && q[0] == 'v' && is_space(q[1])) {
            ++q;
            double c[3];
            for (double& v : c)
                if (!parse_double(q, eol, v)) fail_line(path, line, "malformed vertex (expected 'v x y z').");
            if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
                fail_line(path, line, "vertex coordinate is not a finite number.");
            mesh.vertices.push_back({c[0], c[1], c[2]});
        } else if (eol - q >= 2 && q[0] == 'f' && is_space(q[1])) {
            ++q;
            ++faces;
            poly.clear();
            const long nv = static_cast<long>(mesh.vertices.size());
            while ((q = skip_space(q, eol)) < eol) {
                long i = 0;
                const auto r = std::from_chars(q, eol, i);
                if (r.ec != std::errc() || (r.ptr < eol && !is_space(*r.ptr) && *r.ptr != '/'))
                    fail_line(path, line, "malformed face index.");
                // Negative indices are relative to the vertices read so far (-1 = the last).
                const long idx = i < 0 ? nv + i : i - 1;
                if (i == 0 || idx < 0 || idx > INT32_MAX - 1)
                    fail_line(path, line, "face index " + std::to_string(i) + " is out of range (" +
                                              std::to_string(nv) + " vertices read so far).");
                if (idx >= nv) forward.push_back({line, static_cast<int>(idx)});
                poly.push_back(static_cast<int>(idx));
                q = r.ptr;
                while (q < eol && !is_space(*q)) ++q;  // skip "/vt/vn"
            }
            if (poly.size() < 3) fail_line(path, line, "face has fewer than 3 vertices.");
            for (size_t k = 1; k + 1 < poly.size(); ++k) {
                const int a = poly[0], b = poly[k], c = poly[k + 1];
                // Zero-area by construction: contributes nothing and would spoil edge counts.
                if (a == b || b == c || a == c) continue;
                mesh.triangles.push_back({a, b, c});
            }
        }
        p = next;
    }

    const long nv = static_cast<long>(mesh.vertices.size());
    for (const auto& f : forward)
        if (f.index >= nv)
            fail_line(path, f.line, "face index " + std::to_string(f.index + 1) + " is out of range (the file has " +
                                        std::to_string(nv) + " vertices).");
    if (mesh.vertices.empty() || mesh.triangles.empty())
        fail(path, "has no triangles (" + std::to_string(nv) + " vertices, " + std::to_string(faces) +
                       " faces with distinct vertices read).");

    // Closedness: sort the undirected edges, then every run must have length exactly 2.
    std::vector<uint64_t> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint64_t a = static_cast<uint32_t>(t[k]), b = static_cast<uint32_t>(t[(k + 1) % 3]);
            edges.push_back(a < b ? (a << 32) | b : (b << 32) | a);
        }
    std::sort(edges.begin(), edges.end());
    size_t distinct = 0, open = 0;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i + 1;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        ++distinct;
        if (j - i != 2) ++open;
        i = j;
    }
    if (open > 0) {
        const std::string counts = std::to_string(open) + " of its " + std::to_string(distinct) +
                                   " edges are open (not shared by exactly 2 triangles)";
        if (check == MeshCheck::RequireClosed)
            fail(path, "is not closed: " + counts + ".");
        if (static_cast<double>(open) > 0.01 * static_cast<double>(distinct))
            fail(path, "is not closed: " + counts + ", more than the 1% that small holes may have.");
    }

    Vec3d lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const auto& t : mesh.triangles)
        for (int k : t) {
            const Vec3d& v = mesh.vertices[k];
            lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
            hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
        }
    mesh.lo = lo;
    mesh.hi = hi;

    // "~0" relative to the bounding box: flat, or inconsistently oriented so that it cancels.
    const double ext = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const double vol = mesh.volume();
    if (!(vol > 1e-9 * ext * ext * ext))
        fail(path, "encloses no volume (" + std::to_string(vol) +
                       "); it is flat or its triangles are not consistently oriented.");
    return mesh;
}

}  // namespace sph
