// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/process.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <stdexcept>

namespace mixload {

int runProcess(const ProcessSpec& spec) {
    if (spec.argv.empty()) throw std::invalid_argument("runProcess: empty argv");
    int fds[2];
    if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        ::close(fds[0]);
        ::dup2(fds[1], STDOUT_FILENO);
        ::dup2(fds[1], STDERR_FILENO);
        ::close(fds[1]);
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
    for (;;) {
        const ssize_t n = ::read(fds[0], buf, sizeof buf);
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
