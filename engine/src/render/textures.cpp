// Procedural textures: deterministic, no files.

#include <cmath>

#include "engine/render/renderer.h"

namespace engine {

std::vector<std::uint8_t> makeGroundTexture(int size) {
    // Asphalt-grey tiles with a faint grain and bright grid lines every tile, so motion reads.
    std::vector<std::uint8_t> img(std::size_t(size) * size * 4);
    std::uint32_t seed = 12345;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            seed = seed * 1664525u + 1013904223u;  // a fixed LCG: the same grain every run
            const float grain = float((seed >> 24) & 0x1f) / 31.0f;
            const bool line = x < size / 64 || y < size / 64;
            const bool checker = ((x * 2 / size) + (y * 2 / size)) % 2 == 0;
            float g = (checker ? 0.46f : 0.40f) + 0.05f * grain;
            if (line) g = 0.85f;
            std::uint8_t* p = &img[(std::size_t(y) * size + x) * 4];
            p[0] = std::uint8_t(255 * g * 0.95f);
            p[1] = std::uint8_t(255 * g * 0.97f);
            p[2] = std::uint8_t(255 * g);
            p[3] = 255;
        }
    return img;
}

std::vector<std::uint8_t> makeFlagTexture(int width, int height) {
    // Three horizontal bands with a white disc near the hoist.
    std::vector<std::uint8_t> img(std::size_t(width) * height * 4);
    const std::uint8_t bands[3][3] = {{200, 30, 40}, {245, 245, 240}, {30, 70, 170}};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::uint8_t* c = bands[std::min(2, y * 3 / height)];
            const float dx = (x - 0.3f * width) / height, dy = (y - 0.5f * height) / height;
            const float r = std::sqrt(dx * dx + dy * dy);
            static const std::uint8_t gold[3] = {235, 185, 40};
            if (r < 0.22f) c = gold;
            if (r < 0.17f) c = bands[0];
            std::uint8_t* p = &img[(std::size_t(y) * width + x) * 4];
            p[0] = c[0];
            p[1] = c[1];
            p[2] = c[2];
            p[3] = 255;
        }
    return img;
}

}  // namespace engine
