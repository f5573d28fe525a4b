#pragma once
// Errors that reach the user as one sentence naming the file, key or value at fault.
#include <stdexcept>
#include <string>

namespace sph {

// Bad input from the user (a file, an option, a spec). The harness prints what() and exits 2.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The simulation itself failed (NaN, blow-up, out of memory). The harness prints what() and exits 3.
struct RunError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace sph
