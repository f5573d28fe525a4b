#include "last_good_sink.hpp"

#include "io/snapshot_writer.hpp"

namespace sph {

void LastGoodSink::blow_up(const BlowUpError& e, std::string& where) {
    SnapshotSeries last(directory_, basename_ + "_last_good");
    last.write(e.last_good);
    xdmf_ = last.xdmf_path();
    where += "; the last good state is in " + xdmf_;
}

}  // namespace sph
