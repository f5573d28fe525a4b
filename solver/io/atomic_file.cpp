#include "io/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include <unistd.h>

#include "core/error.hpp"

namespace sph {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    if (path_.empty()) throw RunError("cannot write a file with an empty path");
    // The pid keeps two runs writing into the same folder from clobbering each other's
    // temporaries, and tells a human which run left one behind.
    temp_path_ = path_ + ".tmp-" + std::to_string(static_cast<long>(::getpid()));

    const fs::path parent = fs::path(path_).parent_path();
    if (!parent.empty()) {
        std::error_code ec;
        fs::create_directories(parent, ec);
        // create_directories reports an error when the path exists as a non-directory;
        // re-check so that a pre-existing directory is never treated as a failure.
        if (ec || !fs::is_directory(parent)) {
            const std::string why = ec ? ec.message() : "exists and is not a directory";
            throw RunError("cannot create directory '" + parent.string() + "' for output file '" +
                           path_ + "': " + why);
        }
    }
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : path_(std::move(other.path_)),
      temp_path_(std::move(other.temp_path_)),
      stream_(std::move(other.stream_)),
      committed_(other.committed_),
      active_(other.active_) {
    other.active_ = false;
}

AtomicFile::~AtomicFile() {
    if (!active_ || committed_) return;
    if (stream_.is_open()) stream_.close();
    std::error_code ec;  // best effort: a destructor must not throw
    fs::remove(temp_path_, ec);
}

std::ofstream& AtomicFile::stream() {
    if (committed_) throw RunError("output file '" + path_ + "' was already committed");
    if (!stream_.is_open()) {
        errno = 0;
        // Binary mode: what the caller writes is exactly what lands in the file.
        stream_.open(temp_path_, std::ios::out | std::ios::trunc | std::ios::binary);
        if (!stream_.is_open()) {
            const std::string why = errno ? std::strerror(errno) : "open failed";
            throw RunError("cannot open '" + temp_path_ + "' to write '" + path_ + "': " + why);
        }
    }
    return stream_;
}

void AtomicFile::commit() {
    if (!active_) throw RunError("commit() on a moved-from AtomicFile");
    if (committed_) throw RunError("output file '" + path_ + "' was already committed");
    if (stream_.is_open()) {
        // A failed write (disk full, I/O error) only shows up in the stream state;
        // checking it here is what keeps a short file from being renamed into place.
        stream_.flush();
        const bool write_ok = !stream_.fail();
        stream_.close();
        if (!write_ok || stream_.fail())
            throw RunError("error while writing output file '" + path_ + "' (disk full?)");
    }
    std::error_code ec;
    fs::rename(temp_path_, path_, ec);  // atomic replace within one filesystem (POSIX rename)
    if (ec)
        throw RunError("cannot move '" + temp_path_ + "' to output file '" + path_ +
                       "': " + ec.message());
    committed_ = true;
}

}  // namespace sph
