#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"
#include "scenes/scene.hpp"

namespace sph {

double SceneOptions::number(const std::string& key, double fallback, double lo, double hi) {
    double v = fallback;
    if (auto it = values_.find(key); it != values_.end()) {
        const std::string& s = it->second;
        char* end = nullptr;
        v = std::strtod(s.c_str(), &end);
        if (s.empty() || *end != '\0' || !std::isfinite(v))
            throw InputError("option '" + key + "' must be a number, got '" + s + "'");
    }
    if (v < lo || v > hi) {
        std::ostringstream m;
        m << "option '" << key << "' = " << v << " is outside its range [" << lo << ", " << hi << "]";
        throw InputError(m.str());
    }
    std::ostringstream r;
    r.precision(10);
    r << v;
    resolved_[key] = r.str();
    return v;
}

long long SceneOptions::integer(const std::string& key, long long fallback, long long lo, long long hi) {
    long long v = fallback;
    if (auto it = values_.find(key); it != values_.end()) {
        const std::string& s = it->second;
        auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec != std::errc() || p != s.data() + s.size()) {
            // Accept 2.98e6 style counts as long as they are whole numbers.
            char* end = nullptr;
            const double d = std::strtod(s.c_str(), &end);
            if (s.empty() || *end != '\0' || d != std::floor(d))
                throw InputError("option '" + key + "' must be a whole number, got '" + s + "'");
            v = (long long)d;
        }
    }
    if (v < lo || v > hi)
        throw InputError("option '" + key + "' = " + std::to_string(v) + " is outside its range [" +
                         std::to_string(lo) + ", " + std::to_string(hi) + "]");
    resolved_[key] = std::to_string(v);
    return v;
}

std::string SceneOptions::text(const std::string& key, const std::string& fallback) {
    auto it = values_.find(key);
    const std::string v = it == values_.end() ? fallback : it->second;
    resolved_[key] = v;
    return v;
}

void SceneOptions::finish(const std::string& scene) const {
    for (const auto& [k, v] : values_) {
        if (resolved_.count(k)) continue;
        std::string known;
        for (const auto& [rk, rv] : resolved_) known += (known.empty() ? "" : ", ") + rk;
        throw InputError("unknown option '" + k + "' for scene '" + scene + "' (it knows: " + known + ")");
    }
}

std::string find_mesh(const std::string& file_name) {
    namespace fs = std::filesystem;
    if (fs::path(file_name).has_parent_path()) return file_name;  // a path given explicitly
    std::vector<fs::path> places;
    if (const char* dir = std::getenv("SPH_MESH_DIR")) places.emplace_back(dir);
#ifdef SPH_SOURCE_DIR
    places.emplace_back(fs::path(SPH_SOURCE_DIR) / ".." / "shared" / "meshes");
#endif
    places.emplace_back(fs::path("..") / "shared" / "meshes");
    places.emplace_back(fs::path("shared") / "meshes");
    std::string tried;
    for (const auto& p : places) {
        if (fs::exists(p / file_name)) return (p / file_name).string();
        tried += (tried.empty() ? "" : ", ") + p.string();
    }
    throw InputError("mesh '" + file_name + "' was not found in " + tried +
                     " (set SPH_MESH_DIR or give mesh=PATH)");
}

}  // namespace sph
