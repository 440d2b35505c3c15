#include "render/frame_aa.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <barrier>
#include <thread>

namespace engine {

namespace {

// A contrast of a quarter of the local luma (FXAA's "low quality" threshold) leaves the ground's
// texture alone and meets the edges of the geometry; on the edge test it lands closer to the
// frame at twice the resolution than the lower thresholds do (tests/engine/test_runtime_render.cpp).
constexpr float kContrast = 0.25f, kContrastMin = 0.0625f, kSubpixel = 0.75f;
constexpr int kSearchSteps = 10;
constexpr int kStride[kSearchSteps] = {1, 1, 1, 1, 2, 2, 2, 2, 4, 8};  // whole pixels: no interpolation along the edge

// The original frame: its luma and colours, sampled at pixel centres (x, y) or between them.
struct Source {
    const float* luma;
    const std::uint8_t* rgba;
    int w, h;

    float at(int x, int y) const { return luma[std::size_t(y) * w + x]; }
    // The colour `offset` pixels from pixel (x, y) across a horizontal edge (along y) or a
    // vertical one (along x): linear between the two pixels around that point, clamped to the
    // frame.
    void colourAcross(int x, int y, bool horizontal, float offset, std::uint8_t* out) const {
        const float at = float(horizontal ? y : x) + offset;
        const int last = (horizontal ? h : w) - 1;
        const float clamped = std::clamp(at, 0.0f, float(last));
        const int i0 = std::min(int(clamped), last - 1);
        const float f = clamped - float(i0);
        const std::uint8_t* a = rgba + (horizontal ? std::size_t(i0) * w + x : std::size_t(y) * w + i0) * 4;
        const std::uint8_t* b = a + (horizontal ? std::size_t(w) * 4 : 4);
        for (int k = 0; k < 3; ++k) out[k] = std::uint8_t((1 - f) * float(a[k]) + f * float(b[k]) + 0.5f);
    }
};

// The offset across the edge at pixel (x, y), in pixels toward its side (along `across`): from
// the search along the edge, and the sub-pixel blend.
struct Edge {
    bool horizontal;
    float across;  // +1 or -1: toward the next row (horizontal) or column
};

// The luma half a pixel across the edge from pixel (x, y) + t along it: the mean of the pixel
// there and its neighbour across (t whole: no interpolation along the edge).
float acrossMean(const Source& src, int x, int y, Edge e, int t) {
    const int dx = e.horizontal ? 0 : int(e.across), dy = e.horizontal ? int(e.across) : 0;
    const int px = std::clamp(x + (e.horizontal ? t : 0), 0, src.w - 1), py = std::clamp(y + (e.horizontal ? 0 : t), 0, src.h - 1);
    const int qx = std::clamp(px + dx, 0, src.w - 1), qy = std::clamp(py + dy, 0, src.h - 1);
    return 0.5f * (src.at(px, py) + src.at(qx, qy));
}

float searchOffset(const Source& src, int x, int y, Edge e, float m, float gradient, float edgeMean) {
    int t1 = -1, t2 = 1;  // how far along each way
    float d1 = acrossMean(src, x, y, e, t1) - edgeMean, d2 = acrossMean(src, x, y, e, t2) - edgeMean;
    bool done1 = std::abs(d1) >= gradient, done2 = std::abs(d2) >= gradient;
    for (int i = 0; i < kSearchSteps && !(done1 && done2); ++i) {
        if (!done1) {
            t1 -= kStride[i];
            d1 = acrossMean(src, x, y, e, t1) - edgeMean;
            done1 = std::abs(d1) >= gradient;
        }
        if (!done2) {
            t2 += kStride[i];
            d2 = acrossMean(src, x, y, e, t2) - edgeMean;
            done2 = std::abs(d2) >= gradient;
        }
    }
    const float to1 = float(-t1), to2 = float(t2);
    const bool nearer1 = to1 < to2;
    // Blend only if the luma at the nearer end moves away from this pixel's side of the mean.
    const bool agrees = ((nearer1 ? d1 : d2) < 0) != (m < edgeMean);
    return agrees ? 0.5f - std::min(to1, to2) / (to1 + to2) : 0.0f;
}

// Whether each pixel of row y (but the first and the last) sits on an edge (edge[x] != 0): the
// contrast of it and its four neighbours against the threshold. Branch-free, so that it
// vectorizes.
void markEdges(const Source& src, int y, float* __restrict edge) {
    const float *__restrict row = src.luma + std::size_t(y) * src.w, *__restrict up = row - src.w,
                            *__restrict down = row + src.w;
    for (int x = 1; x + 1 < src.w; ++x) {
        const float m = row[x], n = up[x], s = down[x], e = row[x + 1], w = row[x - 1];
        const float lo = std::min(std::min(std::min(m, n), std::min(s, e)), w);
        const float hi = std::max(std::max(std::max(m, n), std::max(s, e)), w);
        edge[x] = hi - lo >= std::max(kContrastMin, hi * kContrast) ? 1.0f : 0.0f;
    }
}

// The new colour of pixel (x, y), which sits on an edge (markEdges), into `out`.
void blendPixel(const Source& src, int x, int y, std::uint8_t* out) {
    const float m = src.at(x, y), n = src.at(x, y - 1), s = src.at(x, y + 1), e = src.at(x + 1, y), w = src.at(x - 1, y);
    const float range = std::max(std::max(std::max(m, n), std::max(s, e)), w) - std::min(std::min(std::min(m, n), std::min(s, e)), w);
    const float ne = src.at(x + 1, y - 1), nw = src.at(x - 1, y - 1), se = src.at(x + 1, y + 1), sw = src.at(x - 1, y + 1);
    // The edge runs along the direction of the smaller second difference.
    const float acrossRows = std::abs(sw + nw - 2 * w) + 2 * std::abs(n + s - 2 * m) + std::abs(se + ne - 2 * e);
    const float acrossColumns = std::abs(nw + ne - 2 * n) + 2 * std::abs(w + e - 2 * m) + std::abs(sw + se - 2 * s);
    const bool horizontal = acrossRows >= acrossColumns;
    const float before = horizontal ? n : w, after = horizontal ? s : e;
    const bool towardBefore = std::abs(before - m) >= std::abs(after - m);
    const Edge edge{horizontal, towardBefore ? -1.0f : 1.0f};
    const float gradient = 0.25f * std::max(std::abs(before - m), std::abs(after - m));
    const float edgeMean = 0.5f * (m + (towardBefore ? before : after));
    float offset = searchOffset(src, x, y, edge, m, gradient, edgeMean);
    // Sub-pixel features: the 3x3 mean against this pixel.
    const float mean = (2 * (n + s + e + w) + ne + nw + se + sw) / 12;
    float sub = std::clamp(std::abs(mean - m) / range, 0.0f, 1.0f);
    sub = (3 - 2 * sub) * sub * sub;
    offset = std::max(offset, sub * sub * kSubpixel);
    src.colourAcross(x, y, horizontal, offset * edge.across, out);
}

using Change = FrameAntiAliasing::Change;

// Every `stride`-th row from `first` (edges gather where the vehicle and the flag are: rows in
// turn keep two threads' shares alike): the changes of their pixels, but the pixels of `keep`.
void blendRows(const Source& src, int first, int stride, const FrameAntiAliasing::Rect& keep, std::vector<Change>& out) {
    std::vector<float> edge(std::size_t(src.w), 0.0f);
    for (int y = 1 + first; y + 1 < src.h; y += stride) {
        markEdges(src, y, edge.data());
        if (y >= keep[1] && y < keep[3])
            std::fill(edge.begin() + std::clamp(keep[0], 0, src.w), edge.begin() + std::clamp(keep[2], 0, src.w), 0.0f);
        for (int x = 1; x + 1 < src.w; ++x) {
            // Most of a row has no edge: skip four clear pixels at a time.
            std::uint64_t four[2];
            if (x + 4 < src.w) {
                std::memcpy(four, &edge[std::size_t(x)], sizeof four);
                if ((four[0] | four[1]) == 0) {
                    x += 3;
                    continue;
                }
            }
            if (edge[std::size_t(x)] == 0.0f) continue;
            Change c{std::uint32_t(y) * std::uint32_t(src.w) + std::uint32_t(x), {}};
            blendPixel(src, x, y, c.rgb);
            out.push_back(c);
        }
    }
}

// Luma of the pixels [begin, end).
void lumaOf(const std::uint8_t* __restrict rgba, float* __restrict luma, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        luma[i] = 0.299f / 255 * float(rgba[4 * i]) + 0.587f / 255 * float(rgba[4 * i + 1]) +
                  0.114f / 255 * float(rgba[4 * i + 2]);
}

}  // namespace

// Two threads: the rasterizer's are idle once the frame is read back. Each computes half the
// luma, then (once both halves are there) the changes of every other row; the changes are applied
// after every pixel was read, so no pixel reads another's new colour: the same bits either way.
void FrameAntiAliasing::apply(std::vector<std::uint8_t>& rgba, int width, int height, const Rect* keep) {
    if (width < 3 || height < 3 || rgba.size() < std::size_t(width) * height * 4) return;
    const std::size_t n = std::size_t(width) * height;
    luma_.resize(n);
    const Source src{luma_.data(), rgba.data(), width, height};
    const Rect kept = keep ? Rect{(*keep)[0] - 1, (*keep)[1] - 1, (*keep)[2] + 1, (*keep)[3] + 1} : Rect{0, 0, 0, 0};
    std::barrier lumaDone(2);
    auto work = [&](int half) {
        lumaOf(rgba.data(), luma_.data(), n * std::size_t(half) / 2, n * std::size_t(half + 1) / 2);
        lumaDone.arrive_and_wait();
        changes_[half].clear();
        blendRows(src, half, 2, kept, changes_[half]);
    };
    std::thread second(work, 1);
    work(0);
    second.join();
    for (const std::vector<Change>& list : changes_)
        for (const Change& c : list) std::memcpy(rgba.data() + std::size_t(c.pixel) * 4, c.rgb, 3);
}

}  // namespace engine
