#pragma once
// Particle snapshots as one HDF5 file per step plus an XDMF index that ParaView opens
// as a time series (File > Open <basename>.xmf; either the "XDMF Reader" or the
// "Xdmf3 Reader" works, because the point cells are given explicitly).
//
// Per file <dir>/<basename>_<step, 6 digits>.h5:
//   /position      n x 3  float64  (absolute, metres)
//   /velocity      n x 3  float32
//   /density       n      float32
//   /pressure      n      float32
//   /type          n      uint8    (0 fluid, 1 boundary)
//   /id            n      uint32
//   /connectivity  n      uint32   0..n-1: the Polyvertex cells; without it the Xdmf3
//                                  readers build no cells and show nothing by default
//   root attributes: time (float64), step (int64)
#include <cstdint>
#include <string>
#include <vector>

namespace sph {

struct SnapshotData {
    double time = 0.0;
    long step = 0;
    std::vector<double> position;  // 3*n, xyz interleaved, absolute, metres
    std::vector<float> velocity;   // 3*n, xyz interleaved
    std::vector<float> density;    // n
    std::vector<float> pressure;   // n
    std::vector<std::uint8_t> type;  // n, 0 fluid, 1 boundary
    std::vector<std::uint32_t> id;   // n
};

class SnapshotSeries {
public:
    // Touches no file yet; the directory is created by the first write().
    // Throws InputError if basename is empty or contains '/', ':' or a control character
    // (':' would break the "file.h5:/dataset" references in the .xmf).
    SnapshotSeries(std::string directory, std::string basename);

    // Writes <dir>/<basename>_<step>.h5, then rewrites <dir>/<basename>.xmf listing every
    // snapshot written so far by this object, both atomically. Writing a step again
    // replaces that snapshot. Throws RunError naming the file on any failure, or if the
    // array sizes in `data` disagree (n is taken from data.type.size()).
    void write(const SnapshotData& data);

    // Paths (<dir>/<name>.h5) of the snapshots written so far, in write order.
    std::vector<std::string> files() const;

    // Path of the XDMF index, <dir>/<basename>.xmf.
    std::string xdmf_path() const;

private:
    struct Entry {
        std::string file_name;  // relative to directory_, as referenced by the .xmf
        double time;
        long step;
        std::size_t n;
    };

    void write_xdmf() const;

    std::string directory_;
    std::string basename_;
    std::vector<Entry> entries_;
};

}  // namespace sph
