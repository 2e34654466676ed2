// Independent jobs over the threads of this process: the map's grid values, the ensemble's copies,
// the fit's population and local runs. Which thread runs which job is not fixed, so a job's result
// must depend on its index alone (each writes its own slot).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace rubcont {

// Calls job(i) for every i in 0 … n − 1 over min(threads, n) threads (threads ≥ 1; the calling
// thread is one of them) and returns when all are done. The first exception a job throws is
// rethrown here; the jobs not yet started are then skipped. The integrations of every job count
// in the caller's current WorkAccount (solvers/ode.h).
void ParallelFor(int n, int threads, const std::function<void(int)>& job);

// The threads for a "threads" option: the value itself when positive, one per core for 0.
int ThreadsFor(int requested);

// Independent jobs whose results are byte strings, run somewhere — over the threads of this
// process (ThreadJobs), or over the ranks of an MPI run (apps/ranks.h) — and returned in index order
// to every caller. A job's result must depend on its index alone, so that a study that uses them
// computes the same numbers however the jobs are spread.
using JobRunner =
    std::function<std::vector<std::string>(int n, const std::function<std::string(int)>& job)>;

// The jobs over `threads` threads (ParallelFor; threads ≥ 1).
JobRunner ThreadJobs(int threads);

}  // namespace rubcont
