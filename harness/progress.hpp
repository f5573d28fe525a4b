#pragma once
// Progress of a long run on a terminal: one line rewritten in place with the time left.
// Silent when stderr is not a terminal, so CI logs stay quiet.
#include <chrono>
#include <string>

namespace sph {

class Progress {
public:
    Progress(std::string label, bool enabled);
    // `fraction` of the work done (0 to 1), for the percentage and the time left; `detail` says
    // where the run is ("step 12/100, t = 0.01 s"). Redrawn at most every 200 ms, and when done.
    void update(double fraction, const std::string& detail);
    void finish();

private:
    std::string label_;
    bool enabled_;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace sph
