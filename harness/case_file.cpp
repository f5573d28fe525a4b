// Strict parsing of case files (TOML): every message starts with "file:line:".
#include "case_file.hpp"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <new>

#undef TOML_HEADER_ONLY
#define TOML_HEADER_ONLY 1
#include <toml++/toml.h>

#include "core/error.hpp"
#include "experiment_spec.hpp"
#include "gauge_options.hpp"
#include "gauge_tables.hpp"
#include "out_of_memory.hpp"
#include "toml_type_name.hpp"
#include "value_range.hpp"

namespace sph {
namespace {

class CaseReader {
public:
    explicit CaseReader(std::string path) : path_(std::move(path)) {}

    std::string at(const toml::source_region& where) const {
        return path_ + (where.begin.line > 0 ? ":" + std::to_string(where.begin.line) : "");
    }
    [[noreturn]] void fail(const toml::node& n, const std::string& message) const {
        throw InputError(at(n.source()) + ": " + message);
    }

    void check_keys(const toml::table& t, const std::vector<std::string>& known, const std::string& where) const {
        for (const auto& [key, node] : t) {
            if (std::find(known.begin(), known.end(), std::string(key.str())) != known.end()) continue;
            std::string list;
            for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
            throw InputError(at(key.source()) + ": unknown key '" + std::string(key.str()) + "' in " + where +
                             " (known: " + list + ")");
        }
    }

    const toml::table& table(const toml::node& n, const std::string& where) const {
        if (!n.is_table()) fail(n, where + " must be a table, not " + toml_type_name(n));
        return *n.as_table();
    }
    const toml::node& required(const toml::table& t, const std::string& key, const std::string& where) const {
        const toml::node* n = t.get(key);
        if (!n) fail(t, "missing required key '" + key + "' in " + where);
        return *n;
    }

    double number(const toml::node& n, const std::string& key) const {
        if (!n.is_number()) fail(n, "'" + key + "' must be a number, not " + toml_type_name(n));
        return n.value<double>().value();
    }
    double positive(const toml::node& n, const std::string& key) const {
        const double v = number(n, key);
        if (!(v > 0)) fail(n, "'" + key + "' must be above 0, got " + format_number(v));
        return v;
    }
    std::array<double, 3> point(const toml::node& n, const std::string& key) const {
        const toml::array* a = n.as_array();
        if (!a || a->size() != 3) fail(n, "'" + key + "' must be an array of 3 numbers [x, y, z] in metres");
        std::array<double, 3> p{};
        for (std::size_t i = 0; i < 3; ++i) {
            const toml::node& item = *a->get(i);
            if (!item.is_number()) fail(item, "'" + key + "' must be an array of 3 numbers, and " + toml_type_name(item) + " is not one");
            p[i] = item.value<double>().value();
        }
        return p;
    }
    std::string text(const toml::node& n, const std::string& key) const {
        if (!n.is_string()) fail(n, "'" + key + "' must be a string, not " + toml_type_name(n));
        return n.value<std::string>().value();
    }
    bool boolean(const toml::node& n, const std::string& key) const {
        if (!n.is_boolean()) fail(n, "'" + key + "' must be true or false, not " + toml_type_name(n));
        return n.value<bool>().value();
    }
    int layers(const toml::node& n) const {
        if (!n.is_integer()) fail(n, "'layers' must be an integer, not " + toml_type_name(n));
        const long long v = n.value<long long>().value();
        if (v < 1 || v > 5) fail(n, "'layers' must be 1 to 5, got " + std::to_string(v));
        return int(v);
    }
    // The tables of an array of tables ([[case.fluid]]).
    std::vector<const toml::table*> tables(const toml::node& n, const std::string& where) const {
        const toml::array* a = n.as_array();
        if (!a) fail(n, "'" + where + "' must be an array of tables ([[case." + where + "]]), not " + toml_type_name(n));
        std::vector<const toml::table*> out;
        for (const auto& item : *a) out.push_back(&table(item, "each [[case." + where + "]]"));
        return out;
    }
    void box(const toml::table& t, CaseBox& b, const std::string& where) const {
        b.min = point(required(t, "min", where), "min");
        b.max = point(required(t, "max", where), "max");
        b.where = at(t.source()) + ": " + where;
    }


private:
    std::string path_;
};

// build(), with running out of memory while placing the particles (std::bad_alloc from deep
// inside a fill) told as one sentence naming the scene and the options that sized it. No
// particle count is known before the fill for every scene, and a bound from the tank's
// lattice would refuse scenes that fit, so the refusal comes when the memory does.
Scene within_memory(const std::string& scene, const SettingMap& options, const std::function<Scene()>& build) {
    try {
        return build();
    } catch (const std::bad_alloc&) {
        std::string given;
        for (const auto& [k, v] : options) given += (given.empty() ? "" : ", ") + k + "=" + v;
        throw RunError("scene '" + scene + "' (" + (given.empty() ? "its default options" : given) +
                       ") does not fit this machine's memory: it ran out while placing the particles; " +
                       coarser_scene_advice);
    }
}

// What a case file holds, read and checked once for every reader of it: the scene's boxes and
// meshes, and its gauges (named).
struct CaseContents {
    BoxCase box;
    std::vector<Gauge> gauges;
};

CaseContents read_case_file(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) throw InputError("case file '" + path + "' does not exist");
    const CaseReader r(path);
    toml::table doc;
    try {
        doc = toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        throw InputError(r.at(e.source()) + ": TOML syntax error: " + std::string(e.description()));
    }
    r.check_keys(doc, {"case"}, "the top level of a case file");
    if (!doc.get("case")) throw InputError(path + ": a case file needs a [case] table");
    const toml::table& t = r.table(*doc.get("case"), "[case]");
    std::vector<std::string> known = {"description", "domain", "domain_top", "tank", "fluid", "obstacle", "mesh", "gauges"};
    for (const auto& k : box_case_option_keys()) known.push_back(k);
    r.check_keys(t, known, "[case]");

    BoxCase c;
    c.source = path;
    c.name = case_scene_prefix + path;  // the scene is named as the command line names it
    if (const toml::node* n = t.get("description")) r.text(*n, "description");
    const toml::node& dp = r.required(t, "dp", "[case]");
    c.dp = r.positive(dp, "dp");
    c.dp_where = r.at(dp.source());
    for (const auto& key : box_case_option_keys()) {
        const toml::node* n = t.get(key);
        if (!n || key == "dp") continue;
        c.options[key] = key == "kernel" ? r.text(*n, key) : format_number(r.number(*n, key));
    }
    if (const toml::node* n = t.get("domain")) {
        const toml::array* a = n->as_array();
        if (!a || a->size() != 2) r.fail(*n, "'domain' must be [[xmin, ymin, zmin], [xmax, ymax, zmax]] in metres");
        c.domain_lo = r.point(*a->get(0), "domain");
        c.domain_hi = r.point(*a->get(1), "domain");
        for (int k = 0; k < 3; ++k)
            if (!(c.domain_hi[std::size_t(k)] > c.domain_lo[std::size_t(k)]))
                r.fail(*n, "'domain': its second corner must be above its first on every axis");
        c.has_domain = true;
        c.domain_where = r.at(n->source());
    }
    if (const toml::node* n = t.get("domain_top")) {
        if (c.has_domain) r.fail(*n, "'domain_top' and 'domain' exclude each other: give the top in 'domain'");
        c.domain_top = r.number(*n, "domain_top");
        c.domain_where = r.at(n->source());
    }

    const toml::table& tank = r.table(r.required(t, "tank", "[case]"), "[case.tank]");
    r.check_keys(tank, {"min", "max", "open_top", "layers", "name"}, "[case.tank]");
    r.box(tank, c.tank, "[case.tank]");
    if (const toml::node* n = tank.get("open_top")) c.tank.open_top = r.boolean(*n, "open_top");
    if (const toml::node* n = tank.get("layers")) c.tank.layers = r.layers(*n);
    if (const toml::node* n = tank.get("name")) c.tank.name = r.text(*n, "name");
    std::vector<std::pair<std::string, const toml::node*>> bodies = {{c.tank.name, tank.get("name") ? tank.get("name") : &tank}};
    auto check_name = [&](const std::string& name, const toml::node& n) {
        if (name.empty()) r.fail(n, "a body's 'name' must not be empty");
        for (const auto& [other, where] : bodies)
            if (other == name) r.fail(n, "body name '" + name + "' is used twice (also at " + r.at(where->source()) + ")");
        bodies.emplace_back(name, &n);
    };

    if (const toml::node* n = t.get("fluid")) {
        std::size_t index = 0;
        for (const toml::table* f : r.tables(*n, "fluid")) {
            r.check_keys(*f, {"min", "max", "hydrostatic", "velocity"}, "[[case.fluid]]");
            CaseFluid fluid;
            r.box(*f, fluid, "[[case.fluid]] " + std::to_string(++index));
            if (const toml::node* h = f->get("hydrostatic")) fluid.hydrostatic = r.boolean(*h, "hydrostatic");
            if (const toml::node* v = f->get("velocity")) fluid.velocity = r.point(*v, "velocity");
            c.fluids.push_back(fluid);
        }
    }
    if (const toml::node* n = t.get("obstacle")) {
        for (const toml::table* o : r.tables(*n, "obstacle")) {
            r.check_keys(*o, {"name", "min", "max", "layers"}, "[[case.obstacle]]");
            CaseObstacle obstacle;
            const toml::node& name = r.required(*o, "name", "[[case.obstacle]]");
            obstacle.name = r.text(name, "name");
            check_name(obstacle.name, name);
            r.box(*o, obstacle, "[[case.obstacle]] '" + obstacle.name + "'");
            if (const toml::node* l = o->get("layers")) obstacle.layers = r.layers(*l);
            c.obstacles.push_back(obstacle);
        }
    }
    if (const toml::node* n = t.get("mesh")) {
        for (const toml::table* m : r.tables(*n, "mesh")) {
            r.check_keys(*m, {"file", "height", "min", "up"}, "[[case.mesh]]");
            CaseMesh mesh;
            mesh.file = r.text(r.required(*m, "file", "[[case.mesh]]"), "file");
            mesh.height = r.positive(r.required(*m, "height", "[[case.mesh]]"), "height");
            mesh.min = r.point(r.required(*m, "min", "[[case.mesh]]"), "min");
            if (const toml::node* u = m->get("up")) {
                const std::string up = r.text(*u, "up");
                if (up != "y" && up != "z") r.fail(*u, "'up' must be \"y\" or \"z\", got '" + up + "'");
                mesh.y_up = up == "y";
            }
            mesh.where = r.at(m->source()) + ": [[case.mesh]] '" + mesh.file + "'";
            c.meshes.push_back(mesh);
        }
    }
    if (c.fluids.empty() && c.meshes.empty()) throw InputError(r.at(t.source()) + ": [case] has no [[case.fluid]] and no [[case.mesh]]: no fluid");
    check_box_case(c);

    CaseContents contents;
    if (const toml::node* n = t.get("gauges")) {
        contents.gauges = read_gauge_tables(*n, path, "[[case.gauges]]");
        name_gauges(contents.gauges);
        // A force gauge's body is known here, before any run builds the scene; a position is
        // checked against the built scene's domain (check_gauge), which the spacing sizes.
        for (std::size_t i = 0; i < contents.gauges.size(); ++i) {
            const Gauge& g = contents.gauges[i];
            if (g.kind != GaugeKind::force) continue;
            std::string names;
            bool known_body = false;
            for (const auto& [name, where] : bodies) {
                names += (names.empty() ? "'" : ", '") + name + "'";
                known_body = known_body || name == g.body;
            }
            if (!known_body)
                r.fail(*n->as_array()->get(i)->as_table()->get("body"),
                       "[[case.gauges]] " + std::to_string(i + 1) + ": force gauge '" + g.name + "': the case has no body '" +
                           g.body + "' (its bodies: " + names + ")");
        }
    }
    contents.box = std::move(c);
    return contents;
}

}  // namespace

BoxCase load_case_file(const std::string& path) { return read_case_file(path).box; }

std::vector<Gauge> case_gauges(const std::string& scene) {
    if (!is_case_scene(scene)) return {};
    return read_case_file(case_file_of(scene)).gauges;
}

bool is_case_scene(const std::string& scene) { return scene.rfind(case_scene_prefix, 0) == 0; }

std::string case_file_of(const std::string& scene) { return scene.substr(std::string(case_scene_prefix).size()); }

Scene build_scene(const std::string& scene, const SettingMap& options) {
    if (!is_case_scene(scene)) return within_memory(scene, options, [&] { return make_scene(scene, options); });
    const std::string path = case_file_of(scene);
    const BoxCase c = load_case_file(path);
    Scene s;
    try {
        s = within_memory(path, options, [&] { return build_box_case(c, options); });
    } catch (const InputError& e) {
        const std::string m = e.what();
        throw InputError(m.rfind(path, 0) == 0 ? m : path + ": " + m);  // every message names the file
    }
    if (s.fluid_count() == 0) throw InputError(path + ": the case has no fluid particles at dp = " + format_number(s.dp));
    s.settings["case_hash"] = spec_hash(path);
    return s;
}

std::string scene_stem(const std::string& scene) {
    if (!is_case_scene(scene)) return filename_safe(scene);
    return filename_safe(std::filesystem::path(case_file_of(scene)).stem().string());
}

}  // namespace sph
