#pragma once
// A child process the study talks to over its standard input and output (a peer solver that
// lives in another runtime: NVIDIA Newton's, in Python). Its standard error is the study's.

#include <string>
#include <vector>

namespace study {

class PeerProcess {
public:
    // Starts `argv[0]` (a path) with `argv` and the extra environment `env` ("NAME=value").
    // Throws std::runtime_error naming the program when it cannot start.
    PeerProcess(const std::vector<std::string>& argv, const std::vector<std::string>& env);
    ~PeerProcess();  // closes its input and waits for it
    PeerProcess(const PeerProcess&) = delete;
    PeerProcess& operator=(const PeerProcess&) = delete;

    // Writes all of `bytes` / reads exactly `size` bytes; throws std::runtime_error (the peer
    // exited, or closed its end) naming the program.
    void write(const void* bytes, std::size_t size);
    void read(void* bytes, std::size_t size);
    const std::string& program() const { return program_; }

private:
    std::string program_;
    int pid_ = -1, in_ = -1, out_ = -1;  // the child, its stdin (we write), its stdout (we read)
};

}  // namespace study
