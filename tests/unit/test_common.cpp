// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/hash.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"

using namespace mixload;

TEST(Common, StableHashKnownValue) {
    // FNV-1a 64 of "" and "a" (published test vectors).
    EXPECT_EQ(stableHash(""), "cbf29ce484222325");
    EXPECT_EQ(stableHash("a"), "af63dc4c8601ec8c");
}

TEST(Common, RequireRangeMessages) {
    EXPECT_NO_THROW(requireRange("x", 1.0, 0.0, 2.0));
    try {
        requirePositive("d", 0.0);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "invalid d = 0: allowed > 0");
    }
    EXPECT_THROW(requireRange("x", std::nan(""), 0.0, 2.0), InputError);
}

TEST(Common, AtomicWriteLeavesNoTemp) {
    const auto dir = std::filesystem::temp_directory_path() / "mixload_atomic_test";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    writeFileAtomic(dir / "f.txt", "hello");
    writeFileAtomic(dir / "f.txt", "world");
    EXPECT_EQ(readFile(dir / "f.txt"), "world");
    int n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
    EXPECT_EQ(n, 1);
    // Threads writing one file at once never share a temporary: the file ends whole, as one of them wrote it.
    std::vector<std::thread> writers;
    for (int t = 0; t < 4; ++t)
        writers.emplace_back([&, t] {
            for (int i = 0; i < 50; ++i) writeFileAtomic(dir / "f.txt", std::string(1000, static_cast<char>('a' + t)));
        });
    for (auto& w : writers) w.join();
    const auto text = readFile(dir / "f.txt");
    ASSERT_EQ(text.size(), 1000u);
    EXPECT_EQ(text, std::string(1000, text.front()));
    // A file that cannot be written names itself and leaves nothing behind.
    try {
        writeFileAtomic(dir / "no-such-folder" / "g.txt", "x");
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("g.txt"), std::string::npos) << e.what();
    }
    n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
    EXPECT_EQ(n, 1);
    std::filesystem::remove_all(dir);
}

TEST(Common, RunProcessCapturesLinesAndExitCode) {
    std::vector<std::string> lines;
    ProcessSpec spec;
    spec.argv = {"sh", "-c", "echo one; echo two; exit 3"};
    spec.onLine = [&](const std::string& l) { lines.push_back(l); };
    EXPECT_EQ(runProcess(spec), 3);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[1], "two");
}

// Exits 0 when, after a stop request, a tool runs to its own exit code and a solver is stopped at once.
[[noreturn]] static void stopRequestThenRunBoth() {
    stopOnSignals();
    std::raise(SIGTERM);
    ProcessSpec tool;
    tool.argv = {"sh", "-c", "sleep 1; exit 4"};
    tool.stopOnRequest = false;
    const int toolRc = runProcess(tool);
    ProcessSpec solver;
    solver.argv = {"sleep", "30"};
    bool stopped = false;
    const auto t0 = std::chrono::steady_clock::now();
    try {
        runProcess(solver);
    } catch (const DeadlineReached& e) {
        stopped = std::string(e.what()).find("stopped on request") != std::string::npos;
    }
    const bool quick = std::chrono::steady_clock::now() - t0 < std::chrono::seconds(10);
    std::exit(toolRc == 4 && stopped && quick ? 0 : 1);
}

TEST(Common, AStopRequestEndsSolversButLetsToolsFinish) {
    // In a child process of its own: a stop request cannot be taken back in this one.
    EXPECT_EXIT(stopRequestThenRunBoth(), ::testing::ExitedWithCode(0), "");
}

TEST(Common, RunProcessGivesTheChildNoOtherDescriptor) {
    // A descriptor the parent holds (an HDF5 file another worker has open, with its lock) must not
    // live on in the child.
    const auto dir = std::filesystem::temp_directory_path() / "mixload-test-fds";
    std::filesystem::create_directories(dir);
    const int held = ::open((dir / "held").c_str(), O_CREAT | O_WRONLY, 0644);
    ASSERT_GE(held, 3);
    ProcessSpec spec;
    std::vector<std::string> lines;
    spec.argv = {"sh", "-c", "ls /proc/$$/fd"};
    spec.onLine = [&](const std::string& l) { lines.push_back(l); };
    EXPECT_EQ(runProcess(spec), 0);
    ::close(held);
    std::filesystem::remove_all(dir);
    for (const auto& l : lines) EXPECT_LE(std::stoi(l), 2) << "the child has descriptor " << l << " open";
    EXPECT_EQ(lines.size(), 3u);
}

TEST(Common, ParseNumberTakesOnlyWholeStrings) {
    EXPECT_EQ(parseNumber("0.01"), 0.01);
    EXPECT_EQ(parseNumber("21.67900250528"), 21.67900250528);
    EXPECT_EQ(parseNumber("1e-3"), 1e-3);
    EXPECT_EQ(parseNumber("0"), 0.0);
    for (const char* s : {"", "coarse", "0.01m", " 1", "1 ", "0.orig"})
        EXPECT_FALSE(parseNumber(s).has_value()) << '"' << s << '"';
}
