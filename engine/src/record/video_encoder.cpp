#include "engine/record/video_encoder.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

extern char** environ;

namespace engine {

std::unique_ptr<VideoEncoder> VideoEncoder::start(const std::string& path, int width, int height, double fps,
                                                  std::string* error) {
    if (width % 2 || height % 2) {
        if (error) *error = "video size " + std::to_string(width) + "x" + std::to_string(height) +
                            " must be even for yuv420p";
        return nullptr;
    }
    // A closed pipe must be an error we report, not a signal that kills the process.
    std::signal(SIGPIPE, SIG_IGN);
    int fds[2];
    if (pipe(fds) != 0) {
        if (error) *error = std::string("cannot create a pipe for ffmpeg: ") + std::strerror(errno);
        return nullptr;
    }
    auto enc = std::unique_ptr<VideoEncoder>(new VideoEncoder());
    enc->path_ = path;
    enc->frameBytes_ = std::size_t(width) * height * 4;
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    char rate[32];
    std::snprintf(rate, sizeof rate, "%g", fps);
    const std::string part = path + ".part";
    std::vector<std::string> args = {"ffmpeg", "-hide_banner", "-loglevel", "error", "-y",
                                     "-f", "rawvideo", "-pix_fmt", "rgba", "-s", size, "-r", rate,
                                     "-i", "-", "-c:v", "libx264", "-preset", "veryfast", "-crf", "20",
                                     "-pix_fmt", "yuv420p", "-f", "mp4", part};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
    posix_spawn_file_actions_addclose(&actions, fds[1]);
    // Its own process group: a Ctrl-C meant for us must not kill the encoder mid-file; we stop
    // feeding it and it finishes the video cleanly.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);
    const int rc = posix_spawnp(&enc->pid_, "ffmpeg", &actions, &attr, argv.data(), environ);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[0]);
    if (rc != 0) {
        close(fds[1]);
        if (error) *error = std::string("cannot start ffmpeg (is it installed?): ") + std::strerror(rc);
        return nullptr;
    }
    enc->fd_ = fds[1];
    enc->worker_ = std::thread([e = enc.get()] { e->work(); });
    return enc;
}

VideoEncoder::~VideoEncoder() {
    std::string ignored;
    finish(&ignored);
}

void VideoEncoder::push(const std::vector<std::uint8_t>& rgba) {
    std::unique_lock lock(mutex_);
    hasRoom_.wait(lock, [this] { return queue_.size() < 4 || failed_; });
    if (failed_ || closing_) return;
    queue_.push_back(rgba);
    hasWork_.notify_one();
}

void VideoEncoder::work() {
    for (;;) {
        std::vector<std::uint8_t> frame;
        {
            std::unique_lock lock(mutex_);
            hasWork_.wait(lock, [this] { return !queue_.empty() || closing_; });
            if (queue_.empty()) return;
            frame = std::move(queue_.front());
            queue_.pop_front();
            hasRoom_.notify_one();
            if (failed_) continue;
        }
        std::size_t done = 0;
        while (done < frame.size()) {
            const ssize_t n = write(fd_, frame.data() + done, frame.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                std::lock_guard lock(mutex_);
                failed_ = true;
                error_ = path_ + ": ffmpeg stopped reading frames: " + std::strerror(errno);
                hasRoom_.notify_all();
                break;
            }
            done += std::size_t(n);
        }
    }
}

bool VideoEncoder::finish(std::string* error) {
    {
        std::lock_guard lock(mutex_);
        if (finished_) {
            if (error) *error = error_;
            return error_.empty();
        }
        finished_ = closing_ = true;
    }
    hasWork_.notify_all();
    if (worker_.joinable()) worker_.join();
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
    int status = 0;
    if (pid_ > 0) {
        while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        if (error_.empty() && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
            error_ = path_ + ": ffmpeg failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
    }
    const std::string part = path_ + ".part";
    if (error_.empty() && std::rename(part.c_str(), path_.c_str()) != 0)
        error_ = path_ + ": cannot rename the finished video into place";
    if (!error_.empty()) std::remove(part.c_str());
    if (error) *error = error_;
    return error_.empty();
}

}  // namespace engine
