#pragma once
// Post-process anti-aliasing of a finished frame (FXAA-class, after Lottes 2009-2011), on the
// CPU, on the frame as read back: one pass over the pixels, which leaves every pixel without an
// edge as it is and blends the others across the edge they sit on.
//
// Why on the CPU: on a software rasterizer (llvmpipe) a fragment shader runs every instruction
// for every pixel, its early exit included (the branch is masked, not skipped), so the same pass
// as a shader costs the whole edge search at every pixel; here only the few pixels on an edge
// (about 5% of a demo frame) pay for it.
//
// Per pixel, on luma (0.299 r + 0.587 g + 0.114 b): the contrast of it and its four neighbours;
// under max(kContrastMin, kContrast * the local maximum), the pixel stays. Else the edge's
// direction (horizontal or vertical, from the second differences across the 3x3 block), its side
// (the steeper neighbour), a search along it both ways, half a pixel toward that side, in growing
// strides, for where the luma leaves the edge's mean by a quarter of the gradient; from the nearer
// end, the offset across the edge to sample at (0.5 at an end, 0 in the middle of a long edge),
// raised by a sub-pixel blend where the 3x3 mean differs from the pixel. The new colour is the
// bilinear sample of the original frame at that offset.

#include <array>
#include <cstdint>
#include <vector>

namespace engine {

class FrameAntiAliasing {
public:
    // A rectangle of pixels (x0, y0, x1, y1: [x0, x1) x [y0, y1)).
    using Rect = std::array<int, 4>;
    // Anti-aliases `rgba` (width x height, 4 bytes per pixel, rows top-down) in place. `keep`, if
    // given, and a pixel around it stay as they are (the panel drawn into the frame: its text is
    // not blended, and it is not blended into the scene around it).
    void apply(std::vector<std::uint8_t>& rgba, int width, int height, const Rect* keep = nullptr);

    // A pixel's new colour, applied once every pixel has been read.
    struct Change {
        std::uint32_t pixel;
        std::uint8_t rgb[3];
    };

private:
    std::vector<float> luma_;
    std::vector<std::vector<Change>> changes_{2};  // per thread
};

}  // namespace engine
