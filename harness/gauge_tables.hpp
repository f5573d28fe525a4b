#pragma once
// Gauges written as TOML tables: a spec's [[gauges]] and a case file's [[case.gauges]] (the
// same keys as --gauge, gauge_options.hpp: kind, name and the kind's keys, each value a number
// or a string). One reader for both, so that the two files take the same gauges with the same
// words. Include it after defining TOML_HEADER_ONLY, as the spec and case readers do.
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "gauge.hpp"

namespace sph {

// The gauges of `node`, an array of tables of `file` written as `table` ("[[gauges]]",
// "[[case.gauges]]"), in their order. Unnamed ones stay unnamed: they are named KIND<n> where
// the run's gauges are put together (merge_gauges), so that an unnamed gauge never takes the
// name of another list's gauge. Throws InputError "FILE:LINE: ..." naming the table and the
// key: a value that is neither a number nor a string, a missing 'kind', an unknown kind or
// key, a missing key of the kind, a name given twice, or one an unnamed gauge would be given.
std::vector<Gauge> read_gauge_tables(const toml::node& node, const std::string& file, const std::string& table);

}  // namespace sph
