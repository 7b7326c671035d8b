// Ensembles across machines: under mpirun (Open MPI) each rank runs the members with
// index % size == rank and rank 0 gathers them, by index, into the result a single process would
// have made (the same CSV bytes and statistics). Built with MPI only when CMake finds it
// (EOMC_WITH_MPI); otherwise, or when not launched by mpirun, this process is rank 0 of 1.
#pragma once

#include <cstddef>

#include "host/ensemble.hpp"

namespace eomc::host {

class MpiSession {
public:
    MpiSession();  // MPI_Init only when launched by mpirun
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    std::size_t rank() const { return rank_; }
    std::size_t size() const { return size_; }

    // Every rank's members onto rank 0, in index order (wall time: the slowest rank's). Collective:
    // every rank calls it. Returns true on rank 0, which then holds the whole result.
    bool gather(EnsembleResult& result) const;

private:
    bool active_ = false;
    std::size_t rank_ = 0, size_ = 1;
};

}  // namespace eomc::host
