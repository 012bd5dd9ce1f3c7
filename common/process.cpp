// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/process.hpp"

#include <poll.h>
#include <sys/prctl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <stdexcept>

namespace mixload {

namespace {
volatile std::sig_atomic_t gStop = 0;
volatile std::sig_atomic_t gWatching = 0;
extern "C" void askStop(int) { gStop = 1; }
}  // namespace

void stopOnSignals() {
    struct sigaction sa {};
    sa.sa_handler = askStop;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    ::sigaction(SIGTERM, &sa, nullptr);
    ::sigaction(SIGINT, &sa, nullptr);
    gWatching = 1;
}

bool stopRequested() { return gStop != 0; }

bool timeIsUp(const std::optional<std::chrono::steady_clock::time_point>& deadline) {
    return stopRequested() || (deadline && std::chrono::steady_clock::now() >= *deadline);
}

int runProcess(const ProcessSpec& spec) {
    if (spec.argv.empty()) throw std::invalid_argument("runProcess: empty argv");
    int fds[2];
    if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
    const pid_t parent = ::getpid();
    // Until exec the child would keep askStop as its handler: a stop sent to it then (the parent's
    // SIGTERM as soon as the child exists) only set the child's flag, and the solver it became ran to
    // its end (seen in Common.AStopRequestEndsSolversButLetsToolsFinish: 30 s instead of at once). The
    // signals are held across the fork; the child takes the default actions back before it lets them in.
    sigset_t stopSignals, before;
    sigemptyset(&stopSignals);
    sigaddset(&stopSignals, SIGTERM);
    sigaddset(&stopSignals, SIGINT);
    ::sigprocmask(SIG_BLOCK, &stopSignals, &before);
    const pid_t pid = ::fork();
    if (pid != 0) ::sigprocmask(SIG_SETMASK, &before, nullptr);
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        ::signal(SIGTERM, SIG_DFL);
        ::signal(SIGINT, SIG_DFL);
        ::sigprocmask(SIG_SETMASK, &before, nullptr);
        // The child dies with its parent: a driver killed with SIGKILL must not leave a solver
        // writing into a case that the next driver will resume.
        ::prctl(PR_SET_PDEATHSIG, SIGTERM);
        // The parent may have died before prctl: the orphan then belongs to init or to a
        // subreaper, whatever its pid.
        if (::getppid() != parent) _exit(127);
        ::dup2(fds[1], STDOUT_FILENO);
        ::dup2(fds[1], STDERR_FILENO);
        // Nothing else the parent has open goes with the child. A campaign's second worker may be
        // writing or reading an HDF5 file at this fork: a copy of that descriptor in the solver
        // would hold the file's lock for the solver's whole life (2026-12-04: point 8 of v2-holdout
        // then could not open its own start, "unable to lock the file", and lost its first attempt),
        // and a copy of the other worker's pipe would keep that worker's solver output from ending.
        if (::close_range(3, ~0U, 0) != 0)
            for (int fd = 3, n = static_cast<int>(::sysconf(_SC_OPEN_MAX)); fd < n; ++fd) ::close(fd);
        if (!spec.cwd.empty()) {
            if (::chdir(spec.cwd.c_str()) != 0) _exit(127);
            // OpenFOAM warns on every stack frame when PWD disagrees with the real cwd.
            ::setenv("PWD", spec.cwd.c_str(), 1);
        }
        for (const auto& [k, v] : spec.env) ::setenv(k.c_str(), v.c_str(), 1);
        std::vector<char*> args;
        for (const auto& a : spec.argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        ::execvp(args[0], args.data());
        std::fprintf(stderr, "cannot execute %s\n", args[0]);
        _exit(127);
    }
    ::close(fds[1]);
    std::ofstream log;
    if (!spec.log.empty()) log.open(spec.log, std::ios::app);
    std::string pending;
    char buf[8192];
    bool stopped = false;
    for (;;) {
        const bool watchSignals = gWatching && spec.stopOnRequest;
        if ((spec.deadline || watchSignals) && !stopped) {
            const auto now = std::chrono::steady_clock::now();
            if ((watchSignals && gStop) || (spec.deadline && now >= *spec.deadline)) {
                ::kill(pid, SIGTERM);
                stopped = true;
                continue;
            }
            long long wait = 1000;  // ms: a stop asked for by a signal is seen within a second
            if (spec.deadline)
                wait = std::min<long long>(wait, std::chrono::duration_cast<std::chrono::milliseconds>(*spec.deadline - now).count() + 1);
            pollfd pfd{fds[0], POLLIN, 0};
            const int ready = ::poll(&pfd, 1, static_cast<int>(std::max<long long>(wait, 0)));
            if (ready == 0 || (ready < 0 && errno == EINTR)) continue;
        }
        const ssize_t n = ::read(fds[0], buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        if (log) log.write(buf, n);
        if (!spec.onLine) continue;
        pending.append(buf, static_cast<size_t>(n));
        size_t pos;
        while ((pos = pending.find('\n')) != std::string::npos) {
            spec.onLine(pending.substr(0, pos));
            pending.erase(0, pos + 1);
        }
    }
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (stopped) throw DeadlineReached(spec.argv.front() + (gStop && spec.stopOnRequest ? " stopped on request (a signal)" : " stopped at the deadline"));
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return 1;
}

std::string tailLines(const std::filesystem::path& file, int n) {
    std::ifstream is(file);
    std::deque<std::string> lines;
    std::string line;
    while (std::getline(is, line)) {
        lines.push_back(line);
        if (static_cast<int>(lines.size()) > n) lines.pop_front();
    }
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

}  // namespace mixload
