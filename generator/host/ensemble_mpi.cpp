#include "host/ensemble_mpi.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

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
        to.push_back(std::move(m));
    }
}

bool launched_by_mpirun() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
        if (std::getenv(name)) return true;
    return false;
}

}  // namespace

MpiSession::MpiSession() {
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

bool MpiSession::gather(EnsembleResult& result) const {
    if (!active_ || size_ == 1) return true;
    const std::string mine = pack(result.members);
    if (mine.size() > static_cast<std::size_t>(INT32_MAX)) throw std::runtime_error("a rank's ensemble rows exceed 2 GiB");
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(size_), offsets(size_);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string all;
    if (rank_ == 0) {
        std::size_t total = 0;
        for (std::size_t r = 0; r < size_; ++r) {
            offsets[r] = static_cast<int>(total);
            total += static_cast<std::size_t>(counts[r]);
        }
        if (total > static_cast<std::size_t>(INT32_MAX)) throw std::runtime_error("the ensemble rows exceed 2 GiB");
        all.resize(total);
    }
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

MpiSession::MpiSession() = default;
MpiSession::~MpiSession() = default;
bool MpiSession::gather(EnsembleResult&) const { return true; }

#endif

}  // namespace eomc::host
