#pragma once
// Splits [0, n) over `threads` workers in chunks handed out in order (private to pf2_surface).
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace pf2 {
namespace surface_detail {

template <typename Fn>  // fn(worker, begin, end)
void parallelChunks(std::size_t n, int threads, std::size_t chunk, const Fn& fn) {
  threads = std::max(1, std::min<int>(threads, static_cast<int>((n + chunk - 1) / std::max<std::size_t>(chunk, 1))));
  if (threads <= 1) {
    if (n > 0) fn(0, std::size_t{0}, n);
    return;
  }
  std::atomic<std::size_t> next{0};
  // An exception (std::bad_alloc on a huge volume) in any worker is rethrown in the caller's thread
  // after all have stopped, instead of terminating the program from a worker.
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
  const auto work = [&](int worker) {
    try {
      for (;;) {
        const std::size_t begin = next.fetch_add(chunk);
        if (begin >= n) return;
        fn(worker, begin, std::min(n, begin + chunk));
      }
    } catch (...) {
      errors[static_cast<std::size_t>(worker)] = std::current_exception();
      next = n;  // the others stop at their next chunk
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& thread : pool) thread.join();
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

}  // namespace surface_detail
}  // namespace pf2
