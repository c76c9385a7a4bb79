#include "brume/cli/distributed_render.h"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#ifdef BRUME_WITH_MPI
#include <mpi.h>
#endif

namespace brume::cli {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Under mpirun (Open MPI, MPICH/Hydra or a PMIx launcher) rather than started by hand.
bool launchedByMpirun() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(v)) return true;
    return false;
}

#ifdef BRUME_WITH_MPI
// Film sums are 16-byte integers: an MPI type of 16 bytes and an operation that adds them.
// Integer addition is associative and commutative, so the reduction's order does not matter.
extern "C" void addSums(void* in, void* inout, int* count, MPI_Datatype*) {
    const Film::Sum* a = static_cast<const Film::Sum*>(in);
    Film::Sum* b = static_cast<Film::Sum*>(inout);
    for (int i = 0; i < *count; ++i) {
        Film::Sum x, y;
        std::memcpy(&x, a + i, sizeof x);
        std::memcpy(&y, b + i, sizeof y);
        y += x;
        std::memcpy(b + i, &y, sizeof y);
    }
}

// Σ over ranks of `film`'s sums, passes and splat flags, on rank 0 (in chunks: MPI counts
// are ints).
Film reduceFilms(const Film& film) {
    MPI_Datatype sumType;
    MPI_Type_contiguous(int(sizeof(Film::Sum)), MPI_BYTE, &sumType);
    MPI_Type_commit(&sumType);
    MPI_Op op;
    MPI_Op_create(addSums, 1, &op);
    const std::vector<Film::Sum>& mine = film.sums();
    std::vector<Film::Sum> total(mine.size());
    const size_t chunk = size_t(1) << 24;
    for (size_t at = 0; at < mine.size(); at += chunk) {
        const int n = int(std::min(chunk, mine.size() - at));
        MPI_Reduce(mine.data() + at, total.data() + at, n, sumType, op, 0, MPI_COMM_WORLD);
    }
    MPI_Op_free(&op);
    MPI_Type_free(&sumType);
    int counts[2] = {film.passes(), film.hasSplats() ? 1 : 0}, sums[2] = {0, 0}, flags[2] = {0, 0};
    MPI_Reduce(&counts[0], &sums[0], 1, MPI_INT, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(&counts[1], &flags[1], 1, MPI_INT, MPI_MAX, 0, MPI_COMM_WORLD);
    Film out(film.width(), film.height());
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) out.restore(sums[0], std::move(total), flags[1] != 0);
    return out;
}
#endif

// One pass, `pass`, into `film`.
RenderStats renderPass(const Scene& scene, Integrator& integrator, RenderOptions options, Film& film, int pass) {
    options.spp = 1;
    options.timeBudget = 0;
    options.firstPass = pass;
    options.passStride = 1;
    options.progress = false;
    return render(scene, integrator, options, film);
}

void account(RankReport& r, const RenderStats& s) {
    r.busySeconds += s.seconds;
    r.samples += s.samples;
    r.rays += s.rays;
    r.nonFinite += s.nonFinite;
    r.passes += s.passes;
}

}  // namespace

RankGroup::RankGroup() {
#ifdef BRUME_WITH_MPI
    if (!launchedByMpirun()) return;
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    started_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
#else
    // Without MPI every process of `mpirun -np N` would render the whole image, to the same
    // file. The launcher's environment says how many there are.
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* n = std::getenv(v); n && std::atoi(n) > 1)
            throw std::runtime_error(std::string("this brume was built without MPI, but runs as one of ") + n +
                                     " processes under mpirun (" + v + "); rebuild with libopenmpi-dev installed "
                                     "(CMake option BRUME_MPI=ON), or run it without mpirun");
#endif
}

RankGroup::~RankGroup() {
#ifdef BRUME_WITH_MPI
    if (started_) MPI_Finalize();
#endif
}

bool RankGroup::allOk(bool ok) const {
#ifdef BRUME_WITH_MPI
    if (!started_) return ok;
    int mine = ok ? 1 : 0, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return all == 1;
#else
    return ok;
#endif
}

std::vector<int> RankGroup::ranksDiffering(uint64_t key) const {
    std::vector<int> out;
#ifdef BRUME_WITH_MPI
    if (!started_) return out;
    unsigned long long mine = key;
    std::vector<unsigned long long> all(static_cast<size_t>(size_));
    MPI_Gather(&mine, 1, MPI_UNSIGNED_LONG_LONG, all.data(), 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    if (rank_ == 0)
        for (int r = 1; r < size_; ++r)
            if (all[size_t(r)] != all[0]) out.push_back(r);
#endif
    return out;
}

std::string RankGroup::broadcast(const std::string& bytes) const {
#ifdef BRUME_WITH_MPI
    if (!started_) return bytes;
    unsigned long long n = bytes.size();
    MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    std::string out = rank_ == 0 ? bytes : std::string(size_t(n), '\0');
    if (n > 0) MPI_Bcast(out.data(), int(n), MPI_BYTE, 0, MPI_COMM_WORLD);
    return out;
#else
    return bytes;
#endif
}

DistributedResult renderOnRanks(const RankGroup& group, const Scene& scene, Integrator& integrator,
                                const RenderOptions& options, Film& film, const PassPlan& plan,
                                const std::function<bool()>& interrupted, double checkpointEvery,
                                const std::function<void(const Film&, uint64_t)>& saveCheckpoint) {
#ifndef BRUME_WITH_MPI
    (void)group, (void)scene, (void)integrator, (void)options, (void)film, (void)plan, (void)interrupted;
    (void)checkpointEvery, (void)saveCheckpoint;
    throw std::logic_error("brume was built without MPI");
#else
    const int N = group.size(), me = group.rank();
    MPI_Barrier(MPI_COMM_WORLD);
    const Clock::time_point start = Clock::now();
    Clock::time_point lastSave = start;
    RankReport mine;
    DistributedResult result;

    // A pass that throws on this rank (memory, say) is kept and told at the next agreement:
    // had it left the loop, the other ranks would wait for it in a collective forever.
    auto pass = [&](Film& f, int index) {
        if (result.failure) return RenderStats{};
        try {
            if (me == plan.failRank && index == plan.failPass)
                throw std::runtime_error("a fault made for tests at pass " + std::to_string(index));
            return renderPass(scene, integrator, options, f, index);
        } catch (...) {
            result.failure = std::current_exception();
            return RenderStats{};
        }
    };

    // After each pass or round, all ranks agree: stop (a signal anywhere, a failed pass
    // anywhere, or rank 0's clock past the budget) and save a checkpoint (rank 0's clock).
    enum { kStop = 1, kSave = 2 };
    enum { kInterrupted = 1, kFailed = 2 };
    auto agree = [&](bool last) {
        int local = (interrupted() ? kInterrupted : 0) | (result.failure ? kFailed : 0), any = 0;
        MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_BOR, MPI_COMM_WORLD);
        if (any & kFailed) result.failed = true;
        if (any & kInterrupted) result.stopped = true;
        int decision = 0;
        if (me == 0) {
            if (any || last || (plan.lastPass < 0 && secondsSince(start) >= plan.timeBudget)) decision |= kStop;
            if (!(decision & kStop) && checkpointEvery > 0 && secondsSince(lastSave) >= checkpointEvery) decision |= kSave;
        }
        MPI_Bcast(&decision, 1, MPI_INT, 0, MPI_COMM_WORLD);
        return decision;
    };
    auto nonFiniteSoFar = [&] {
        unsigned long long m = mine.nonFinite, total = 0;
        MPI_Reduce(&m, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
        return uint64_t(total);
    };
    auto save = [&] {
        Film combined = reduceFilms(film);
        const uint64_t nf = nonFiniteSoFar();
        if (me == 0) saveCheckpoint(combined, nf);
        lastSave = Clock::now();
    };

    // The pilot: every rank renders it; ranks other than 0 into a film that is dropped.
    bool stop = false;
    int next = plan.firstPass;
    for (; next < plan.pilotEnd && !stop; ++next) {
        Film scratch(film.width(), film.height());
        RenderStats s = pass(me == 0 ? film : scratch, next);
        if (me == 0) account(mine, s);
        else mine.busySeconds += s.seconds;  // (busy, though its pilot is not in the image)
        const bool last = plan.lastPass >= 0 && next + 1 >= plan.lastPass;
        const int d = agree(last);
        stop = d & kStop;
        if (d & kSave) save();
    }
    // The rounds: rank r renders pass next + k·N + r in round k.
    for (int k = 0; !stop; ++k) {
        const int index = next + k * N + me;
        if (plan.lastPass < 0 || index < plan.lastPass) account(mine, pass(film, index));
        const bool last = plan.lastPass >= 0 && next + (k + 1) * N >= plan.lastPass;
        const int d = agree(last);
        stop = d & kStop;
        if (d & kSave) save();
    }

    // The combined film and every rank's account, on rank 0.
    const double wall = secondsSince(start);
    MPI_Barrier(MPI_COMM_WORLD);
    const Clock::time_point reduceStart = Clock::now();
    Film combined = reduceFilms(film);
    result.reduceSeconds = secondsSince(reduceStart);
    double report[5] = {mine.busySeconds, double(mine.samples), double(mine.rays), double(mine.nonFinite),
                        double(mine.passes)};
    std::vector<double> all(size_t(5 * N));
    MPI_Gather(report, 5, MPI_DOUBLE, all.data(), 5, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (me == 0) {
        film = std::move(combined);
        for (int r = 0; r < N; ++r) {
            const double* a = &all[size_t(5 * r)];
            RankReport rr{a[0], uint64_t(a[1]), uint64_t(a[2]), uint64_t(a[3]), int(a[4])};
            result.ranks.push_back(rr);
            result.stats.samples += rr.samples;
            result.stats.rays += rr.rays;
            result.stats.nonFinite += rr.nonFinite;
            result.stats.passes += rr.passes;
        }
        result.stats.seconds = wall;
    }
    return result;
#endif
}

}  // namespace brume::cli
