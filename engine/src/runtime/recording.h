#pragma once
// What the runtime records of the rendered frames, as the options ask: PNG frames in
// DIR/frames (FrameWriter, on worker threads) and DIR/video.mp4 (VideoEncoder, ffmpeg).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/runtime.h"
#include "engine/scene/scene.h"

namespace engine {

class Recording {
public:
    // Throws ConfigError when the video encoder cannot be started (or this build cannot record).
    Recording(const SceneConfig& scene, const RunOptions& options);
    ~Recording();
    Recording(const Recording&) = delete;
    Recording& operator=(const Recording&) = delete;

    // Hands one rendered frame (RGBA, top-down) to the frame writer and the video encoder.
    void write(int frame, const std::vector<std::uint8_t>& rgba);

    // Drains the writers; false with *error when any write failed.
    bool finish(int* framesWritten, std::string* video, std::string* error);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace engine
