#include "solvers/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "solvers/ode.h"

namespace rubcont {

void ParallelFor(int n, int threads, const std::function<void(int)>& job) {
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;
  std::exception_ptr error;
  WorkAccount* const account = CurrentWorkAccount();  // the workers' integrations are the caller's
  auto work = [&]() {
    const WorkScope counting(account);
    for (int i = next.fetch_add(1); i < n && !failed.load(); i = next.fetch_add(1)) {
      try {
        job(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::min(threads, n); ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  if (error) std::rethrow_exception(error);
}

JobRunner ThreadJobs(int threads) {
  return [threads](int n, const std::function<std::string(int)>& job) {
    std::vector<std::string> results(static_cast<std::size_t>(std::max(n, 0)));
    ParallelFor(n, threads, [&](int i) { results[static_cast<std::size_t>(i)] = job(i); });
    return results;
  };
}

int ThreadsFor(int requested) {
  return requested > 0 ? requested : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace rubcont
