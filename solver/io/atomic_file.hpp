#pragma once
// All-or-nothing output files. Content goes to "<path>.tmp-<pid>" and only commit()
// renames it over <path>, so a crash, an exception or a full disk never leaves a
// truncated file under the final name that a later reader would take for complete.
// A temporary left behind by a killed process keeps its ".tmp-<pid>" suffix.
#include <fstream>
#include <string>

namespace sph {

class AtomicFile {
public:
    // Creates the parent directories of `path` now (throws RunError naming them on
    // failure); opens nothing yet, so HDF5 and the like can create temp_path() themselves.
    explicit AtomicFile(std::string path);
    // Removes the temporary unless commit() succeeded. Never throws.
    ~AtomicFile();

    AtomicFile(AtomicFile&& other) noexcept;
    AtomicFile& operator=(AtomicFile&&) = delete;
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    const std::string& path() const { return path_; }
    // Where the content must be written before commit(), for libraries that open by name.
    const std::string& temp_path() const { return temp_path_; }

    // Text/binary stream on temp_path(), opened (truncating) on first call.
    // Throws RunError naming the file if it cannot be opened.
    std::ofstream& stream();

    // Flushes and closes stream() if it was used, checks that every write succeeded,
    // then renames temp_path() over path(). Throws RunError naming path() on failure
    // (the temporary is then removed by the destructor). Calling it twice is an error.
    void commit();

    bool committed() const { return committed_; }

private:
    std::string path_;
    std::string temp_path_;
    std::ofstream stream_;
    bool committed_ = false;
    bool active_ = true;  // false once moved from: the destructor must do nothing
};

}  // namespace sph
