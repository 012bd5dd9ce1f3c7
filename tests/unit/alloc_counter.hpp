// SPDX-License-Identifier: GPL-3.0-or-later
// Counts heap allocations (global operator new, replaced in alloc_counter.cpp) made by the calling
// thread between start and stop, to show that hot paths never allocate.
#pragma once

namespace mixload::testing {
void startCountingAllocations();
long stopCountingAllocations();  // allocations since start
}  // namespace mixload::testing
