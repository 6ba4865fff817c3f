#pragma once
// Splits [0, n) over `threads` workers in chunks handed out in order (private to pf2_surface).
#include <algorithm>
#include <atomic>
#include <cstddef>
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
  const auto work = [&](int worker) {
    for (;;) {
      const std::size_t begin = next.fetch_add(chunk);
      if (begin >= n) return;
      fn(worker, begin, std::min(n, begin + chunk));
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& thread : pool) thread.join();
}

}  // namespace surface_detail
}  // namespace pf2
