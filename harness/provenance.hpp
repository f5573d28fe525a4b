#pragma once
// Where a result came from: every CSV the harness writes starts with these lines.
#include <string>
#include <utility>
#include <vector>

namespace sph {

using Metadata = std::vector<std::pair<std::string, std::string>>;

struct BuildInfo {
    std::string git_commit, git_dirty, build_type, flags, precision, cuda_compiled;
};
BuildInfo build_info();

// Build, backend, devices, the implementation variants (every one, as name=value:
// describe_implementation_variants), host, date and command line, plus anything the caller adds.
Metadata provenance(const std::string& backend, const std::string& devices, const std::string& variants,
                    const std::string& command_line);

std::string utc_now();
// FNV-1a of a program's bytes (by default this one's): results made by another binary are not
// up to date. "unknown" when unreadable.
std::string binary_hash(const std::string& path = "/proc/self/exe");
std::string command_line_of(int argc, char** argv);

}  // namespace sph
