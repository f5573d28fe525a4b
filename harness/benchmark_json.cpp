// Google Benchmark's JSON output (--benchmark_format=json or --benchmark_out) as a result set:
// each benchmark is a run, its repetitions' real_time (in nanoseconds) the samples of the
// metric "real_time". Aggregate rows (mean, median, stddev) are skipped; the verdict makes
// its own statistics from the repetitions.
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <variant>

#include "core/error.hpp"
#include "regression_compare.hpp"

namespace sph {
namespace {

// Just enough JSON for benchmark files: objects, arrays, strings, numbers, literals.
struct Json {
    using Object = std::map<std::string, Json>;
    using Array = std::vector<Json>;
    std::variant<std::nullptr_t, bool, double, std::string, std::shared_ptr<Array>, std::shared_ptr<Object>> value;

    const Object* object() const {
        auto p = std::get_if<std::shared_ptr<Object>>(&value);
        return p ? p->get() : nullptr;
    }
    const Array* array() const {
        auto p = std::get_if<std::shared_ptr<Array>>(&value);
        return p ? p->get() : nullptr;
    }
    const Json* at(const std::string& key) const {
        const Object* o = object();
        if (!o) return nullptr;
        auto it = o->find(key);
        return it == o->end() ? nullptr : &it->second;
    }
};

class JsonParser {
public:
    JsonParser(const std::string& text, const std::string& path) : s_(text), path_(path) {}

    Json document() {
        Json v = value();
        skip_space();
        if (i_ != s_.size()) fail("unexpected text after the document");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        long line = 1;
        for (std::size_t k = 0; k < i_ && k < s_.size(); ++k) line += s_[k] == '\n';
        throw InputError(path_ + ":" + std::to_string(line) + ": invalid JSON: " + what);
    }
    void skip_space() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\r' || s_[i_] == '\t')) ++i_;
    }
    void expect(char c) {
        skip_space();
        if (i_ >= s_.size() || s_[i_] != c) fail(std::string("expected '") + c + "'");
        ++i_;
    }
    bool literal(const char* word) {
        const std::string w(word);
        if (s_.compare(i_, w.size(), w) != 0) return false;
        i_ += w.size();
        return true;
    }
    std::string string() {
        expect('"');
        std::string out;
        while (i_ < s_.size() && s_[i_] != '"') {
            char c = s_[i_++];
            if (c == '\\' && i_ < s_.size()) {
                const char e = s_[i_++];
                if (e == 'n') c = '\n';
                else if (e == 't') c = '\t';
                else if (e == 'u') {  // names are ASCII; keep other code points as '?'
                    if (i_ + 4 > s_.size()) fail("bad \\u escape");
                    const long code = std::strtol(s_.substr(i_, 4).c_str(), nullptr, 16);
                    c = code < 128 ? char(code) : '?';
                    i_ += 4;
                } else c = e;
            }
            out += c;
        }
        if (i_ >= s_.size()) fail("unterminated string");
        ++i_;
        return out;
    }
    Json value() {
        skip_space();
        if (i_ >= s_.size()) fail("unexpected end");
        Json v;
        const char c = s_[i_];
        if (c == '{') {
            ++i_;
            auto obj = std::make_shared<Json::Object>();
            skip_space();
            if (i_ < s_.size() && s_[i_] == '}') ++i_;
            else
                for (;;) {
                    std::string key = string();
                    expect(':');
                    (*obj)[key] = value();
                    skip_space();
                    if (i_ < s_.size() && s_[i_] == ',') { ++i_; continue; }
                    expect('}');
                    break;
                }
            v.value = obj;
        } else if (c == '[') {
            ++i_;
            auto arr = std::make_shared<Json::Array>();
            skip_space();
            if (i_ < s_.size() && s_[i_] == ']') ++i_;
            else
                for (;;) {
                    arr->push_back(value());
                    skip_space();
                    if (i_ < s_.size() && s_[i_] == ',') { ++i_; continue; }
                    expect(']');
                    break;
                }
            v.value = arr;
        } else if (c == '"') {
            v.value = string();
        } else if (literal("true")) {
            v.value = true;
        } else if (literal("false")) {
            v.value = false;
        } else if (literal("null")) {
            v.value = nullptr;
        } else {
            char* end = nullptr;
            const double d = std::strtod(s_.c_str() + i_, &end);
            if (end == s_.c_str() + i_) fail("unexpected character '" + std::string(1, c) + "'");
            i_ = std::size_t(end - s_.c_str());
            v.value = d;
        }
        return v;
    }

    const std::string& s_;
    std::string path_;
    std::size_t i_ = 0;
};

double to_nanoseconds(const std::string& unit) {
    if (unit == "ns" || unit.empty()) return 1;
    if (unit == "us") return 1e3;
    if (unit == "ms") return 1e6;
    if (unit == "s") return 1e9;
    throw InputError("unknown benchmark time_unit '" + unit + "'");
}

}  // namespace

ResultSet load_benchmark_json(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    const std::string content = text.str();
    const Json doc = JsonParser(content, path).document();
    const Json* benchmarks = doc.at("benchmarks");
    if (!benchmarks || !benchmarks->array())
        throw InputError("'" + path + "' is not Google Benchmark JSON (no \"benchmarks\" array)");
    ResultSet set;
    set.source = path;
    for (const Json& b : *benchmarks->array()) {
        auto text_of = [&](const char* key) -> std::string {
            const Json* v = b.at(key);
            const std::string* s = v ? std::get_if<std::string>(&v->value) : nullptr;
            return s ? *s : std::string();
        };
        if (text_of("run_type") == "aggregate") continue;
        if (const Json* err = b.at("error_occurred"); err && std::get_if<bool>(&err->value) && std::get<bool>(err->value))
            continue;
        const Json* real = b.at("real_time");
        const double* t = real ? std::get_if<double>(&real->value) : nullptr;
        if (!t) continue;
        std::string name = text_of("run_name");
        if (name.empty()) name = text_of("name");
        RunSamples& run = set.runs[name];
        run.all_steps_files = false;
        run.run_values["real_time"].push_back(*t * to_nanoseconds(text_of("time_unit")));
    }
    return set;
}

}  // namespace sph
