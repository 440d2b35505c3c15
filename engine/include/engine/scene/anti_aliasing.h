#pragma once
// How a frame is anti-aliased (a scene's render.aa, --aa; the renderer's choice).

#include <string_view>

namespace engine {

// Off: not at all. Msaa: the main pass multisampled. Post: one pass over the finished frame
// (FXAA-class). Auto: the pass on a software rasterizer (llvmpipe, softpipe: every sample costs
// CPU time there), multisampling on a GPU.
enum class AntiAliasing { Auto, Off, Msaa, Post };
const char* toString(AntiAliasing aa);  // "auto", "off", "msaa", "post"
// The mode a word names (as toString writes it); false for any other word.
bool antiAliasingOf(std::string_view word, AntiAliasing& out);

}  // namespace engine
