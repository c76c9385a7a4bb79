// One render on several processes (MPI ranks, `mpirun -np N brume render ...`): docs/mpi.md.
//
// The unit of work is the pass. Every rank renders whole passes into a film of its own and
// the films are summed at the end; the film's sums are exact (film/film.h), so the image is
// the same, bit for bit, as one process rendering the same passes, whatever the number of
// ranks and threads. The passes after those already done (a resumed checkpoint) go to the
// ranks in rounds: in round k rank r renders pass start + k·N + r. All ranks agree after every
// round whether to stop (a signal, the time budget, the last pass) and whether to save a
// checkpoint, so the passes completed are always a prefix of the pass sequence and a
// checkpoint can be resumed on any number of ranks. With `--integrator auto` every rank renders
// the pilot passes itself (its statistics and its decision are deterministic, so all ranks
// decide the same), and only rank 0's film keeps them.
//
// Without MPI (or outside mpirun) there is one rank and none of this runs.
#pragma once
#include <cstdint>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "brume/film/film.h"
#include "brume/render/renderer.h"

namespace brume::cli {

// This process's place in the job. A RankGroup started under mpirun finalizes MPI when it
// goes out of scope.
class RankGroup {
public:
    RankGroup();  // starts MPI if brume was built with it and runs under mpirun
    ~RankGroup();
    RankGroup(const RankGroup&) = delete;
    RankGroup& operator=(const RankGroup&) = delete;
    int rank() const { return rank_; }
    int size() const { return size_; }
    bool distributed() const { return size_ > 1; }

    // True on every rank iff `ok` is true on every rank (a collective: all ranks must call it).
    bool allOk(bool ok) const;
    // The ranks whose `key` differs from rank 0's (empty on ranks other than 0).
    std::vector<int> ranksDiffering(uint64_t key) const;
    // Rank 0's bytes, on every rank.
    std::string broadcast(const std::string& bytes) const;

private:
    int rank_ = 0, size_ = 1;
    bool started_ = false;
};

// What the ranks render: passes [firstPass, lastPass) (lastPass < 0: until the time budget is
// spent), the pilot passes [firstPass, pilotEnd) on every rank (pilotEnd ≤ firstPass: none).
struct PassPlan {
    int firstPass = 0;
    int lastPass = -1;
    int pilotEnd = 0;
    double timeBudget = 0;  // seconds, with lastPass < 0
    // For tests (render's hidden --fail-at-pass RANK:PASS): rank failRank throws when it
    // starts pass failPass, as a rank that runs out of memory would.
    int failRank = -1, failPass = -1;
};

// A rank's own account, gathered on rank 0.
struct RankReport {
    double busySeconds = 0;  // rendering
    uint64_t samples = 0, rays = 0, nonFinite = 0;
    int passes = 0;
};

struct DistributedResult {
    RenderStats stats;               // combined: passes, samples, rays, non-finite; seconds = wall time
    std::vector<RankReport> ranks;   // rank 0 only: one per rank
    double reduceSeconds = 0;        // the final reduction of the films (rank 0's view)
    bool stopped = false;            // by a signal
    // A pass failed on some rank (an exception in its render): every rank stopped at the next
    // agreement, and `failure` holds this rank's own error (null where it was another's).
    bool failed = false;
    std::exception_ptr failure;
};

// Renders `plan` on all ranks. `film` holds what is done already (rank 0: a resumed
// checkpoint's sums; other ranks: empty) and on return, on rank 0, the whole render.
// `interrupted` is polled between passes; `saveCheckpoint` (rank 0) is called with the
// combined film of a prefix of passes every `checkpointEvery` seconds (0: never).
DistributedResult renderOnRanks(const RankGroup& group, const Scene& scene, Integrator& integrator,
                                const RenderOptions& options, Film& film, const PassPlan& plan,
                                const std::function<bool()>& interrupted, double checkpointEvery,
                                const std::function<void(const Film&, uint64_t nonFinite)>& saveCheckpoint);

}  // namespace brume::cli
