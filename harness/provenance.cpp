#include "provenance.hpp"

#include "multi/rank_group.hpp"

#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>
#include <memory>

#include "backend/subdomain.hpp"
#include "experiment_spec.hpp"

#ifndef SPH_GIT_COMMIT
#define SPH_GIT_COMMIT "unknown"
#endif
#ifndef SPH_GIT_DIRTY
#define SPH_GIT_DIRTY "unknown"
#endif
#ifndef SPH_BUILD_TYPE
#define SPH_BUILD_TYPE "unknown"
#endif
#ifndef SPH_BUILD_FLAGS
#define SPH_BUILD_FLAGS ""
#endif

namespace sph {
namespace {

// The live repository state when the binary runs inside one; the configure-time state otherwise.
std::string git(const char* args) {
    const std::string cmd = std::string("git -C \"") + SPH_SOURCE_DIR + "\" " + args + " 2>/dev/null";
    std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
    if (!p) return "";
    std::string out;
    std::array<char, 256> buf{};
    while (fgets(buf.data(), buf.size(), p.get())) out += buf.data();
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
}

}  // namespace

BuildInfo build_info() {
    BuildInfo b;
    const char* env_commit = std::getenv("SPH_GIT_COMMIT");
    const char* env_dirty = std::getenv("SPH_GIT_DIRTY");
    const std::string live = env_commit ? "" : git("rev-parse HEAD");
    b.git_commit = env_commit ? env_commit : (live.empty() ? SPH_GIT_COMMIT : live);
    if (env_dirty) b.git_dirty = env_dirty;
    else if (!live.empty()) b.git_dirty = git("status --porcelain --untracked-files=no").empty() ? "clean" : "dirty";
    else b.git_dirty = SPH_GIT_DIRTY;
    b.build_type = SPH_BUILD_TYPE;
    b.flags = SPH_BUILD_FLAGS;
#ifdef SPH_DOUBLE
    b.precision = "float64";
#else
    b.precision = "float32";
#endif
#ifdef SPH_HAVE_CUDA
    b.cuda_compiled = "yes";
#else
    b.cuda_compiled = "no";
#endif
    return b;
}

std::string binary_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "unknown";
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return fnv1a_hex(bytes.str());
}

std::string utc_now() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

std::string command_line_of(int argc, char** argv) {
    std::string s;
    for (int i = 0; i < argc; ++i) {
        if (i > 0) s.push_back(' ');
        s.append(argv[i]);
    }
    return s;
}

Metadata provenance(const std::string& backend, const std::string& devices, const std::string& variants,
                    const std::string& command_line) {
    const BuildInfo b = build_info();
    char host[256] = "unknown";
    gethostname(host, sizeof host - 1);
    const std::string cuda = cuda_device_summary();
    return {{"git_commit", b.git_commit},
            {"git_dirty", b.git_dirty},
            {"build_type", b.build_type},
            {"build_flags", b.flags},
            {"precision", b.precision},
            {"cuda_compiled", b.cuda_compiled},
            {"backend", backend},
            {"devices", devices},
            {"implementation_variants", variants},
            {"processes", process_ranks().description()},
            {"cuda", cuda.empty() ? "none" : cuda},
            {"host", host},
            {"date", utc_now()},
            {"command_line", command_line}};
}

}  // namespace sph
