#include "peer_process.h"

#include <csignal>
#include <cstring>
#include <stdexcept>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace study {

namespace {

std::runtime_error failure(const std::string& program, const std::string& what) {
    return std::runtime_error("peer '" + program + "': " + what);
}

}  // namespace

PeerProcess::PeerProcess(const std::vector<std::string>& argv, const std::vector<std::string>& env) : program_(argv.at(0)) {
    int toChild[2], fromChild[2];
    if (pipe(toChild) != 0) throw failure(program_, std::string("pipe: ") + std::strerror(errno));
    if (pipe(fromChild) != 0) {
        close(toChild[0]), close(toChild[1]);
        throw failure(program_, std::string("pipe: ") + std::strerror(errno));
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, toChild[0], 0);
    posix_spawn_file_actions_adddup2(&actions, fromChild[1], 1);
    for (int fd : {toChild[0], toChild[1], fromChild[0], fromChild[1]}) posix_spawn_file_actions_addclose(&actions, fd);
    std::vector<std::string> environment(env);
    for (char** e = environ; *e; ++e) environment.emplace_back(*e);
    std::vector<char*> args, envp;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    for (const std::string& e : environment) envp.push_back(const_cast<char*>(e.c_str()));
    args.push_back(nullptr), envp.push_back(nullptr);
    const int spawned = posix_spawn(&pid_, program_.c_str(), &actions, nullptr, args.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    close(toChild[0]), close(fromChild[1]);
    in_ = toChild[1], out_ = fromChild[0];
    if (spawned != 0) {
        close(in_), close(out_), pid_ = -1;
        throw failure(program_, std::string("cannot start: ") + std::strerror(spawned));
    }
    std::signal(SIGPIPE, SIG_IGN);  // a peer that exits makes write() fail, not the study
}

PeerProcess::~PeerProcess() {
    if (in_ >= 0) close(in_);
    if (out_ >= 0) close(out_);
    if (pid_ > 0) waitpid(pid_, nullptr, 0);
}

void PeerProcess::write(const void* bytes, std::size_t size) {
    const char* p = static_cast<const char*>(bytes);
    while (size > 0) {
        const ssize_t n = ::write(in_, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw failure(program_, "exited or closed its input");
        p += n, size -= std::size_t(n);
    }
}

void PeerProcess::read(void* bytes, std::size_t size) {
    char* p = static_cast<char*>(bytes);
    while (size > 0) {
        const ssize_t n = ::read(out_, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw failure(program_, "exited before it answered (its own message is above)");
        p += n, size -= std::size_t(n);
    }
}

}  // namespace study
