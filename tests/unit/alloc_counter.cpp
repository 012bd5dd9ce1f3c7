// SPDX-License-Identifier: GPL-3.0-or-later
#include "alloc_counter.hpp"

#include <cstdlib>
#include <new>

namespace {
thread_local bool tCounting = false;
thread_local long tAllocations = 0;

void* countedAlloc(std::size_t n) {
    if (tCounting) ++tAllocations;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return countedAlloc(n); }
void* operator new[](std::size_t n) { return countedAlloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace mixload::testing {
void startCountingAllocations() {
    tAllocations = 0;
    tCounting = true;
}
long stopCountingAllocations() {
    tCounting = false;
    return tAllocations;
}
}  // namespace mixload::testing
