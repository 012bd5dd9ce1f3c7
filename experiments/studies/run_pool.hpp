// SPDX-License-Identifier: GPL-3.0-or-later
// Runs n independent jobs on `jobs` threads with one progress bar; results are recorded by the
// callback under the pool's lock.
#pragma once
#include <algorithm>
#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/progress.hpp"

namespace mixload::experiments {

// work(i) runs outside the lock; record(i, result) runs under it.
template <class Result>
void runPool(size_t n, int jobs, const std::string& label, bool progress,
             const std::function<Result(size_t)>& work,
             const std::function<void(size_t, const Result&)>& record) {
    std::atomic<size_t> next{0}, done{0};
    std::mutex m;
    Progress bar(label, progress);
    const auto worker = [&] {
        for (size_t i; (i = next++) < n;) {
            const Result r = work(i);
            std::lock_guard<std::mutex> lock(m);
            record(i, r);
            bar.update(double(++done) / n, std::to_string(done) + "/" + std::to_string(n) + " runs");
        }
    };
    std::vector<std::thread> pool;
    for (int j = 0; j < std::max(1, jobs); ++j) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    bar.finish();
}

}  // namespace mixload::experiments
