#pragma once
// Progress of a long run on a terminal: one line rewritten in place with the time left.
// Silent when stderr is not a terminal, so CI logs stay quiet.
#include <chrono>
#include <string>

namespace sph {

class Progress {
public:
    Progress(std::string label, long total, bool enabled);
    void update(long done, const std::string& detail = "");
    void finish();

private:
    std::string label_;
    long total_;
    bool enabled_;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace sph
