// Ensembles across machines: under mpirun (Open MPI) each rank runs the members with
// index % size == rank and rank 0 gathers them, by index, into the result a single process would
// have made (the same CSV bytes and statistics). Built with MPI only when CMake finds it
// (EOMC_WITH_MPI); otherwise, or when not launched by mpirun, this process is rank 0 of 1.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <string>
#include <utility>

#include "host/ensemble.hpp"

namespace eomc::host {

// The error a job ends with, agreed by every rank (MpiSession::agree): the exit status of the
// first failing rank's error and, on rank 0 alone, the text the one-process run prints for it
// (the other ranks print nothing). main exits with `status` after printing `text`.
class JobError : public std::exception {
public:
    JobError(int status, std::string text) : status_(status), text_(std::move(text)) {}
    int status() const { return status_; }
    const std::string& text() const { return text_; }
    const char* what() const noexcept override { return text_.c_str(); }

private:
    int status_;
    std::string text_;
};

// An error as main reports it: its exit status and the line it prints.
using ErrorReport = std::function<std::pair<int, std::string>(std::exception_ptr)>;

class MpiSession {
public:
    explicit MpiSession(ErrorReport report);  // MPI_Init only when launched by mpirun
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    std::size_t rank() const { return rank_; }
    std::size_t size() const { return size_; }

    // Runs `work` on this rank and agrees with the others on how it ended (collective: every rank
    // calls it, error or not, so none is left waiting in a later collective while another one
    // unwinds into MPI_Finalize). Returns when it succeeded on every rank; otherwise throws
    // JobError on every rank with the first failing rank's status and, on rank 0, its text. In one
    // process it runs `work`, whose errors propagate as they are.
    void agree(const std::function<void()>& work) const;

    // Every rank's members onto rank 0, in index order (wall time: the slowest rank's). Collective:
    // every rank calls it; the sizes are agreed before anyone throws. Returns true on rank 0, which
    // then holds the whole result.
    bool gather(EnsembleResult& result) const;

private:
    ErrorReport report_;
    bool active_ = false;
    std::size_t rank_ = 0, size_ = 1;
};

}  // namespace eomc::host
