#include "engine/record/frame_writer.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace engine {

namespace {
// libpng reports through these instead of printing; the error one must not return.
void pngError(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void pngWarning(png_structp, png_const_charp) {}
}  // namespace

namespace {

// The libpng part, with no C++ object alive across its setjmp (a longjmp could clobber one).
// 0 when written; else errno from a failed write inside libpng, or -1 for an encoder error.
int encodePng(std::FILE* f, int width, int height, const std::uint8_t* rgba) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, &pngError, &pngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    errno = 0;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        const int err = errno;  // a failed fwrite inside libpng leaves the reason here
        png_destroy_write_struct(&png, &info);
        return err ? err : -1;
    }
    png_init_io(png, f);
    // Level 1 with the Sub filter: most of the size win for a fraction of the default's time.
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGBA,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y) png_write_row(png, rgba + std::size_t(y) * width * 4);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return 0;
}

}  // namespace

bool writePng(const std::string& path, int width, int height, const std::uint8_t* rgba, std::string* error) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) {
        if (error) *error = path + ": cannot open for writing: " + std::strerror(errno);
        return false;
    }
    const int err = encodePng(f, width, height, rgba);
    if (err != 0) {
        std::fclose(f);
        if (error) *error = path + ": cannot write PNG: " + (err > 0 ? std::strerror(err) : "encoder error") +
                            (err == ENOSPC ? " (disk full)" : "");
        return false;
    }
    const bool flushed = std::fflush(f) == 0;
    const bool closed = std::fclose(f) == 0;
    if (!flushed || !closed) {
        if (error) *error = path + ": write failed: " + std::strerror(errno) + " (disk full?)";
        return false;
    }
    return true;
}

bool readPng(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgba) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str())) return false;
    image.format = PNG_FORMAT_RGBA;
    rgba.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, rgba.data(), 0, nullptr)) {
        png_image_free(&image);
        return false;
    }
    width = int(image.width);
    height = int(image.height);
    return true;
}

std::string FrameWriter::framePath(const std::string& dir, int index) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", index);
    return dir + "/" + name;
}

FrameWriter::FrameWriter(std::string dir, int width, int height, int threads, std::size_t queueFrames)
    : dir_(std::move(dir)), width_(width), height_(height), capacity_(queueFrames) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) error_ = dir_ + ": cannot create folder: " + ec.message();
    for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

FrameWriter::~FrameWriter() { finish(); }

void FrameWriter::push(int index, const std::vector<std::uint8_t>& rgba) {
    std::unique_lock lock(mutex_);
    hasRoom_.wait(lock, [this] { return queue_.size() < capacity_ || !error_.empty(); });
    if (!error_.empty() || closing_) return;
    queue_.emplace_back(index, rgba);
    hasWork_.notify_one();
}

void FrameWriter::work() {
    for (;;) {
        std::pair<int, std::vector<std::uint8_t>> job;
        {
            std::unique_lock lock(mutex_);
            hasWork_.wait(lock, [this] { return !queue_.empty() || closing_; });
            if (queue_.empty()) return;
            job = std::move(queue_.front());
            queue_.pop_front();
            hasRoom_.notify_one();
            if (!error_.empty()) continue;  // after a failure, drop the rest
        }
        const std::string path = framePath(dir_, job.first);
        const std::string tmp = dir_ + "/.tmp_" + path.substr(dir_.size() + 1);
        std::string err;
        bool ok = writePng(tmp, width_, height_, job.second.data(), &err);
        if (ok && std::rename(tmp.c_str(), path.c_str()) != 0) {
            ok = false;
            err = path + ": cannot rename into place: " + std::strerror(errno);
        }
        if (!ok) std::remove(tmp.c_str());
        std::lock_guard lock(mutex_);
        if (ok) ++written_;
        else if (error_.empty()) error_ = err;
        if (!ok) hasRoom_.notify_all();
    }
}

bool FrameWriter::finish() {
    {
        std::lock_guard lock(mutex_);
        if (finished_) return error_.empty();
        closing_ = true;
        finished_ = true;
    }
    hasWork_.notify_all();
    for (auto& t : workers_) t.join();
    workers_.clear();
    return ok();
}

bool FrameWriter::ok() const {
    std::lock_guard lock(mutex_);
    return error_.empty();
}
std::string FrameWriter::error() const {
    std::lock_guard lock(mutex_);
    return error_;
}
int FrameWriter::written() const {
    std::lock_guard lock(mutex_);
    return written_;
}

}  // namespace engine
