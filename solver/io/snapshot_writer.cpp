#include "io/snapshot_writer.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numeric>
#include <ostream>
#include <utility>

#include <hdf5.h>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace sph {

namespace fs = std::filesystem;

namespace {

// ---- HDF5 plumbing -------------------------------------------------------------------

// HDF5 prints its whole error stack to stderr by default. We report failures through
// RunError instead, so printing is switched off while we call into the library and the
// caller's setting is restored afterwards.
class SilenceHdf5Errors {
public:
    SilenceHdf5Errors() {
        H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~SilenceHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
    SilenceHdf5Errors(const SilenceHdf5Errors&) = delete;
    SilenceHdf5Errors& operator=(const SilenceHdf5Errors&) = delete;

private:
    H5E_auto2_t func_ = nullptr;
    void* data_ = nullptr;
};

// The innermost entry of the current error stack is where HDF5 detected the problem
// (e.g. "unable to open file: ... errno = 21, error message = 'Is a directory'").
// Must be read before any other HDF5 call, which would clear the stack.
std::string hdf5_error_detail() {
    std::string detail;
    auto walk = [](unsigned, const H5E_error2_t* err, void* out) -> herr_t {
        if (err && err->desc && *err->desc) *static_cast<std::string*>(out) = err->desc;
        return 0;
    };
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk, &detail);  // downward: innermost last
    return detail.empty() ? "unknown HDF5 error" : detail;
}

// Names the final file (what the user knows) in every error.
[[noreturn]] void fail(const std::string& what, const std::string& file) {
    throw RunError("cannot write snapshot '" + file + "': HDF5 failed to " + what + ": " +
                   hdf5_error_detail());
}

// Owns one HDF5 identifier; closes it on every path out of the scope.
class H5Handle {
public:
    using Closer = herr_t (*)(hid_t);
    H5Handle(hid_t id, Closer closer, const std::string& what, const std::string& file)
        : id_(id), closer_(closer) {
        if (id_ < 0) fail(what, file);
    }
    ~H5Handle() {
        if (id_ >= 0) closer_(id_);
    }
    H5Handle(const H5Handle&) = delete;
    H5Handle& operator=(const H5Handle&) = delete;

    hid_t get() const { return id_; }

    // Explicit close where its result matters (H5Fclose flushes the file to disk).
    void close(const std::string& what, const std::string& file) {
        const hid_t id = std::exchange(id_, -1);
        if (closer_(id) < 0) fail(what, file);
    }

private:
    hid_t id_;
    Closer closer_;
};

void check(herr_t status, const std::string& what, const std::string& file) {
    if (status < 0) fail(what, file);
}

// Writes a contiguous 1-D (cols == 0) or rows x cols dataset.
void write_dataset(hid_t file_id, const char* name, hid_t file_type, hid_t mem_type,
                   const void* data, hsize_t rows, hsize_t cols, const std::string& file) {
    const std::string where = std::string("dataset /") + name;
    const hsize_t dims[2] = {rows, cols};
    H5Handle space(H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose,
                   "create the dataspace of " + where, file);
    H5Handle dset(H5Dcreate2(file_id, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                             H5P_DEFAULT),
                  H5Dclose, "create " + where, file);
    // HDF5 rejects a null buffer even for zero elements, and an empty vector may give one.
    if (rows > 0)
        check(H5Dwrite(dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
              "write " + where, file);
    dset.close("close " + where, file);
}

void write_scalar_attribute(hid_t obj, const char* name, hid_t file_type, hid_t mem_type,
                            const void* value, const std::string& file) {
    const std::string where = std::string("attribute ") + name;
    H5Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create the dataspace of " + where, file);
    H5Handle attr(H5Acreate2(obj, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                  H5Aclose, "create " + where, file);
    check(H5Awrite(attr.get(), mem_type, value), "write " + where, file);
    attr.close("close " + where, file);
}

void write_hdf5(const std::string& temp_path, const std::string& final_path,
                const SnapshotData& d, std::size_t n) {
    const std::string& f = final_path;
    SilenceHdf5Errors quiet;
    H5Handle file(H5Fcreate(temp_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                  "create file '" + temp_path + "'", f);

    // Explicit Polyvertex cells, one point each (see the header for why).
    std::vector<std::uint32_t> connectivity(n);
    std::iota(connectivity.begin(), connectivity.end(), std::uint32_t{0});

    // File types are fixed little-endian so files are identical whatever host wrote them.
    const hid_t fid = file.get();
    write_dataset(fid, "position", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, d.position.data(), n, 3, f);
    write_dataset(fid, "velocity", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, d.velocity.data(), n, 3, f);
    write_dataset(fid, "density", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, d.density.data(), n, 0, f);
    write_dataset(fid, "pressure", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, d.pressure.data(), n, 0, f);
    write_dataset(fid, "type", H5T_STD_U8LE, H5T_NATIVE_UINT8, d.type.data(), n, 0, f);
    write_dataset(fid, "id", H5T_STD_U32LE, H5T_NATIVE_UINT32, d.id.data(), n, 0, f);
    write_dataset(fid, "connectivity", H5T_STD_U32LE, H5T_NATIVE_UINT32, connectivity.data(), n,
                  0, f);

    const std::int64_t step = d.step;
    write_scalar_attribute(fid, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &d.time, f);
    write_scalar_attribute(fid, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &step, f);

    // Everything else is closed by now, so this really flushes and closes the file.
    file.close("close file '" + temp_path + "'", f);
}

// ---- XDMF text ----------------------------------------------------------------------

std::string shortest(double v) {
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return ec == std::errc() ? std::string(buf, end) : std::string("0");
}

std::string xml_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
        }
    }
    return out;
}

void data_item(std::ostream& out, const std::string& file, const char* dataset, std::size_t n,
               bool vector, const char* number_type, int precision) {
    out << "          <DataItem Dimensions=\"" << n << (vector ? " 3" : "") << "\" NumberType=\""
        << number_type << "\" Precision=\"" << precision << "\" Format=\"HDF\">" << file << ":/"
        << dataset << "</DataItem>\n";
}

void attribute(std::ostream& out, const std::string& file, const char* name, std::size_t n,
               bool vector, const char* number_type, int precision) {
    out << "        <Attribute Name=\"" << name << "\" AttributeType=\""
        << (vector ? "Vector" : "Scalar") << "\" Center=\"Node\">\n";
    data_item(out, file, name, n, vector, number_type, precision);
    out << "        </Attribute>\n";
}

std::string step_file_name(const std::string& basename, long step) {
    char digits[32];
    std::snprintf(digits, sizeof digits, "%06ld", step);
    return basename + "_" + digits + ".h5";
}

}  // namespace

// ---- SnapshotSeries -----------------------------------------------------------------

SnapshotSeries::SnapshotSeries(std::string directory, std::string basename)
    : directory_(std::move(directory)), basename_(std::move(basename)) {
    if (basename_.empty()) throw InputError("snapshot basename is empty");
    for (char c : basename_) {
        if (c == '/' || c == ':' || static_cast<unsigned char>(c) < 0x20)
            throw InputError("snapshot basename '" + basename_ +
                             "' must not contain '/', ':' or control characters");
    }
}

std::vector<std::string> SnapshotSeries::files() const {
    std::vector<std::string> out;
    out.reserve(entries_.size());
    for (const Entry& e : entries_) out.push_back((fs::path(directory_) / e.file_name).string());
    return out;
}

std::string SnapshotSeries::xdmf_path() const {
    return (fs::path(directory_) / (basename_ + ".xmf")).string();
}

void SnapshotSeries::write(const SnapshotData& d) {
    const std::string name = step_file_name(basename_, d.step);
    const std::string path = (fs::path(directory_) / name).string();

    // A size mismatch would make HDF5 read past the end of a vector; refuse it up front.
    const std::size_t n = d.type.size();
    auto expect = [&](const char* field, std::size_t have, std::size_t want) {
        if (have != want)
            throw RunError("cannot write snapshot '" + path + "': " + field + " has " +
                           std::to_string(have) + " values, expected " + std::to_string(want) +
                           " for " + std::to_string(n) + " particles");
    };
    if (d.step < 0) throw RunError("cannot write snapshot '" + path + "': negative step");
    expect("position", d.position.size(), 3 * n);
    expect("velocity", d.velocity.size(), 3 * n);
    expect("density", d.density.size(), n);
    expect("pressure", d.pressure.size(), n);
    expect("id", d.id.size(), n);
    if (n > std::numeric_limits<std::uint32_t>::max())
        throw RunError("cannot write snapshot '" + path + "': too many particles");

    {
        AtomicFile out(path);  // removes its temporary if anything below throws
        write_hdf5(out.temp_path(), path, d, n);
        out.commit();
    }

    // The .h5 now exists, so list it even if rewriting the index fails below; the next
    // successful write() will then include it.
    Entry entry{name, d.time, d.step, n};
    auto same = std::find_if(entries_.begin(), entries_.end(),
                             [&](const Entry& e) { return e.file_name == name; });
    if (same != entries_.end())
        *same = entry;
    else
        entries_.push_back(entry);

    write_xdmf();
}

void SnapshotSeries::write_xdmf() const {
    AtomicFile file(xdmf_path());
    std::ostream& out = file.stream();
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
        << "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n"
        << "  <Domain>\n"
        << "    <Grid Name=\"" << xml_escape(basename_)
        << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const Entry& e : entries_) {
        // File names only, no directory: the folder can be moved or copied as a whole.
        const std::string h5 = xml_escape(e.file_name);
        const std::size_t n = e.n;
        char grid_name[32];
        std::snprintf(grid_name, sizeof grid_name, "step_%06ld", e.step);
        out << "      <Grid Name=\"" << grid_name << "\" GridType=\"Uniform\">\n"
            << "        <Time Value=\"" << shortest(e.time) << "\"/>\n"
            << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
            << "\" NodesPerElement=\"1\">\n";
        data_item(out, h5, "connectivity", n, false, "UInt", 4);
        out << "        </Topology>\n"
            << "        <Geometry GeometryType=\"XYZ\">\n";
        data_item(out, h5, "position", n, true, "Float", 8);
        out << "        </Geometry>\n";
        attribute(out, h5, "velocity", n, true, "Float", 4);
        attribute(out, h5, "density", n, false, "Float", 4);
        attribute(out, h5, "pressure", n, false, "Float", 4);
        attribute(out, h5, "type", n, false, "UChar", 1);
        attribute(out, h5, "id", n, false, "UInt", 4);
        out << "      </Grid>\n";
    }
    out << "    </Grid>\n"
        << "  </Domain>\n"
        << "</Xdmf>\n";
    file.commit();
}

}  // namespace sph
