#include "host/ensemble_mpi.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#ifdef EOMC_WITH_MPI
#include <mpi.h>
#endif

namespace eomc::host {

#ifdef EOMC_WITH_MPI

namespace {

// Members as bytes (doubles as their bits, so the gathered values are the computed ones).
void put(std::string& out, const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); }
void put_u64(std::string& out, std::uint64_t v) { put(out, &v, sizeof v); }
void put_text(std::string& out, const std::string& s) {
    put_u64(out, s.size());
    out += s;
}
void put_doubles(std::string& out, const std::vector<double>& v) {
    put_u64(out, v.size());
    put(out, v.data(), v.size() * sizeof(double));
}

struct Reader {
    const char* p;
    const char* end;
    void get(void* to, std::size_t n) {
        if (static_cast<std::size_t>(end - p) < n) throw std::runtime_error("a gathered ensemble member is truncated");
        std::memcpy(to, p, n);
        p += n;
    }
    std::uint64_t u64() {
        std::uint64_t v;
        get(&v, sizeof v);
        return v;
    }
    std::string text() {
        std::string s(u64(), '\0');
        get(s.data(), s.size());
        return s;
    }
    std::vector<double> doubles() {
        std::vector<double> v(u64());
        get(v.data(), v.size() * sizeof(double));
        return v;
    }
};

std::string pack(const std::vector<MemberResult>& members) {
    std::string out;
    for (const auto& m : members) {
        put_u64(out, m.index);
        put_text(out, m.status);
        put_text(out, m.message);
        put(out, &m.t, sizeof m.t);
        put_doubles(out, m.inputs);
        put_doubles(out, m.state);
        put_doubles(out, m.drifts);
        put_doubles(out, m.observed);
        put_u64(out, m.events);
        put_u64(out, m.refused);
        put_text(out, m.refused_at.file);
        put_u64(out, static_cast<std::uint64_t>(m.refused_at.line));
        put_u64(out, static_cast<std::uint64_t>(m.refused_at.column));
        put_text(out, m.refusal);
    }
    return out;
}

void unpack(const char* p, std::size_t n, std::vector<MemberResult>& to) {
    Reader r{p, p + n};
    while (r.p < r.end) {
        MemberResult m;
        m.index = r.u64();
        m.status = r.text();
        m.message = r.text();
        r.get(&m.t, sizeof m.t);
        m.inputs = r.doubles();
        m.state = r.doubles();
        m.drifts = r.doubles();
        m.observed = r.doubles();
        m.events = r.u64();
        m.refused = r.u64() != 0;
        m.refused_at.file = r.text();
        m.refused_at.line = static_cast<int>(r.u64());
        m.refused_at.column = static_cast<int>(r.u64());
        m.refusal = r.text();
        to.push_back(std::move(m));
    }
}

bool launched_by_mpirun() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
        if (std::getenv(name)) return true;
    return false;
}

}  // namespace

MpiSession::MpiSession(ErrorReport report) : report_(std::move(report)) {
    if (!launched_by_mpirun()) return;
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) MPI_Init(nullptr, nullptr);
    active_ = true;
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    rank_ = static_cast<std::size_t>(rank);
    size_ = static_cast<std::size_t>(size);
}

MpiSession::~MpiSession() {
    if (active_) MPI_Finalize();
}

void MpiSession::agree(const std::function<void()>& work) const {
    if (!active_ || size_ == 1) return work();
    std::exception_ptr error;
    try {
        work();
    } catch (...) {
        error = std::current_exception();
    }
    const int mine = error ? static_cast<int>(rank_) : static_cast<int>(size_);
    int first = mine;  // the lowest failing rank; size_ when none failed
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == static_cast<int>(size_)) return;
    std::pair<int, std::string> report{1, ""};
    if (first == static_cast<int>(rank_)) report = report_(error);
    MPI_Bcast(&report.first, 1, MPI_INT, first, MPI_COMM_WORLD);
    if (first != 0) {  // its text to rank 0, which prints it
        std::uint64_t length = report.second.size();
        if (rank_ == static_cast<std::size_t>(first)) {
            MPI_Send(&length, 1, MPI_UINT64_T, 0, 0, MPI_COMM_WORLD);
            MPI_Send(report.second.data(), static_cast<int>(length), MPI_CHAR, 0, 1, MPI_COMM_WORLD);
        } else if (rank_ == 0) {
            MPI_Recv(&length, 1, MPI_UINT64_T, first, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            report.second.assign(length, '\0');
            MPI_Recv(report.second.data(), static_cast<int>(length), MPI_CHAR, first, 1, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
        }
    }
    throw JobError(report.first, rank_ == 0 ? report.second : std::string());
}

bool MpiSession::gather(EnsembleResult& result) const {
    if (!active_ || size_ == 1) return true;
    constexpr std::size_t limit = static_cast<std::size_t>(INT32_MAX);  // MPI counts are ints
    std::string mine;
    agree([&] {
        mine = pack(result.members);
        if (mine.size() > limit)
            throw std::runtime_error(fmt::format("rank {}'s ensemble rows are {} bytes, more than MPI's 2 GiB a "
                                                 "message; run more ranks or fewer --samples",
                                                 rank_, mine.size()));
    });
    const std::uint64_t size = mine.size();
    std::uint64_t total = 0;
    MPI_Allreduce(&size, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    std::string all;
    agree([&] {  // the same verdict on every rank, before anyone gathers
        if (total > limit)
            throw std::runtime_error(fmt::format("the ensemble rows are {} bytes, more than MPI's 2 GiB a gather; "
                                                 "run fewer --samples",
                                                 total));
        if (rank_ == 0) all.resize(total);
    });
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(size_), offsets(size_);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    for (std::size_t r = 1; r < size_; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
    MPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
    double wall = result.wall_s;
    MPI_Reduce(&result.wall_s, &wall, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    if (rank_ != 0) return false;
    result.members.clear();
    unpack(all.data(), all.size(), result.members);
    std::sort(result.members.begin(), result.members.end(),
              [](const MemberResult& a, const MemberResult& b) { return a.index < b.index; });
    result.wall_s = wall;
    result.ranks = size_;
    return true;
}

#else

MpiSession::MpiSession(ErrorReport report) : report_(std::move(report)) {}
MpiSession::~MpiSession() = default;
void MpiSession::agree(const std::function<void()>& work) const { work(); }
bool MpiSession::gather(EnsembleResult&) const { return true; }

#endif

}  // namespace eomc::host
