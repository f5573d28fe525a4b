#pragma once
// What a TOML value is, in the words of an error sentence ("must be a number, not a string"):
// shared by the spec and case-file readers.
#include <string>

#include <toml++/toml.h>

namespace sph {

inline std::string toml_type_name(const toml::node& n) {
    switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date or time";
    }
}

}  // namespace sph
