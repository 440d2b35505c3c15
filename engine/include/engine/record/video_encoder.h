#pragma once
// H.264 video through an ffmpeg child process fed raw RGBA frames over a pipe, on its own thread
// with a bounded queue so encoding runs alongside simulation and rendering.
//   ffmpeg -f rawvideo -pix_fmt rgba -s WxH -r FPS -i - -c:v libx264 -pix_fmt yuv420p OUT.mp4
// The video is encoded to OUT.mp4.part and renamed when ffmpeg succeeds.

#include <sys/types.h>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace engine {

class VideoEncoder {
public:
    // Null with *error when ffmpeg cannot be started or the size is odd.
    static std::unique_ptr<VideoEncoder> start(const std::string& path, int width, int height,
                                               double fps, std::string* error);
    ~VideoEncoder();

    void push(const std::vector<std::uint8_t>& rgba);
    // Closes the pipe and waits for ffmpeg. False with *error when it failed.
    bool finish(std::string* error);

private:
    VideoEncoder() = default;
    void work();
    std::string path_;
    std::size_t frameBytes_ = 0;
    pid_t pid_ = -1;
    int fd_ = -1;
    std::mutex mutex_;
    std::condition_variable hasWork_, hasRoom_;
    std::deque<std::vector<std::uint8_t>> queue_;
    std::thread worker_;
    bool closing_ = false, finished_ = false, failed_ = false;
    std::string error_;
};

}  // namespace engine
