#pragma once
// Writes RGBA frames as PNG files DIR/frame_NNNNNN.png on worker threads, so encoding does not
// serialize with simulation and rendering. The queue is bounded (back-pressure keeps memory
// bounded). Each file is written under a temporary name in the same folder and renamed, so a
// folder never holds a half-written frame. Errors (disk full, unwritable folder) are kept and
// reported, never thrown from a worker.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace engine {

class FrameWriter {
public:
    FrameWriter(std::string dir, int width, int height, int threads = 2, std::size_t queueFrames = 6);
    ~FrameWriter();  // finishes
    FrameWriter(const FrameWriter&) = delete;
    FrameWriter& operator=(const FrameWriter&) = delete;

    // Copies the frame into the queue; blocks while the queue is full. Ignored after an error.
    void push(int index, const std::vector<std::uint8_t>& rgba);
    // Drains the queue and joins the workers. False when any write failed.
    bool finish();
    bool ok() const;
    std::string error() const;
    int written() const;

    static std::string framePath(const std::string& dir, int index);

private:
    void work();
    std::string dir_;
    int width_, height_;
    std::size_t capacity_;
    mutable std::mutex mutex_;
    std::condition_variable hasWork_, hasRoom_;
    std::deque<std::pair<int, std::vector<std::uint8_t>>> queue_;
    std::vector<std::thread> workers_;
    bool closing_ = false, finished_ = false;
    std::string error_;
    int written_ = 0;
};

// PNG encode/decode with libpng (RGBA8, top-down rows).
bool writePng(const std::string& path, int width, int height, const std::uint8_t* rgba, std::string* error);
bool readPng(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgba);

}  // namespace engine
