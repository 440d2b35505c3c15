// Recording of the rendered frames: the frame writer and the video encoder.

#include "runtime/recording.h"

#include "engine/scene/config_error.h"
#include "engine/record/frame_writer.h"
#include "engine/record/video_encoder.h"

namespace engine {

struct Recording::Impl {
    std::unique_ptr<FrameWriter> writer;  // unless --no-frames
    std::unique_ptr<VideoEncoder> video;  // with --video
    std::string videoPath;
};

Recording::Recording(const SceneConfig& scene, const RunOptions& options) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    const int w = scene.render.width, h = scene.render.height;
    std::string error;
    if (!options.noFrames) m.writer = std::make_unique<FrameWriter>(options.outDir + "/frames", w, h);
    if (options.video) {
        m.videoPath = options.outDir + "/video.mp4";
        m.video = VideoEncoder::start(m.videoPath, w, h, scene.fps, &error);
        if (!m.video) throw ConfigError("--video: " + error);
    }
}

Recording::~Recording() = default;

void Recording::write(int frame, const std::vector<std::uint8_t>& rgba) {
    if (impl_->writer) impl_->writer->push(frame, rgba);
    if (impl_->video) impl_->video->push(rgba);
}

bool Recording::finish(int* framesWritten, std::string* video, std::string* error) {
    Impl& m = *impl_;
    bool ok = true;
    std::string err;
    if (m.writer) {
        ok = m.writer->finish();
        if (!ok) err = m.writer->error();
        *framesWritten = m.writer->written();
    }
    if (m.video) {
        std::string verr;
        if (m.video->finish(&verr)) *video = m.videoPath;
        else {
            ok = false;
            if (err.empty()) err = verr;
        }
    }
    if (!ok && error) *error = err;
    return ok;
}

}  // namespace engine
