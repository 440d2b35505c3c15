// Rendered frames through the runtime (headless, OSMesa): determinism, content, input replay.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "engine/render/gl_context.h"
#include "engine/render/renderer.h"
#include "engine/runtime.h"

using namespace engine;

namespace {

SceneConfig small(const char* name, int w = 320, int h = 180) {
    SceneConfig s = loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/" + name + ".json");
    s.subsystems &= ~kRecording;
    s.render.width = w;
    s.render.height = h;
    s.render.shadowMapSize = 512;
    return s;
}

std::uint64_t fnv1a(const std::vector<std::uint8_t>& bytes) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint8_t b : bytes) h = (h ^ b) * 1099511628211ull;
    return h;
}

std::vector<std::uint64_t> frameHashes(const SceneConfig& s, const RunOptions& o) {
    Runtime rt(s, o);
    std::vector<std::uint64_t> hashes;
    while (rt.frame()) hashes.push_back(fnv1a(rt.pixels()));
    rt.finish();
    return hashes;
}

std::string tempPath(const char* name) {
    return (std::filesystem::temp_directory_path() / name).string();
}

}  // namespace

TEST(RuntimeRender, TwoRunsOfTheSameSceneAndScriptGiveIdenticalFrames) {
    RunOptions o;
    o.frames = 40;
    const auto a = frameHashes(small("flag_vehicle"), o);
    const auto b = frameHashes(small("flag_vehicle"), o);
    ASSERT_EQ(a.size(), 40u);
    EXPECT_EQ(a, b);
    EXPECT_NE(a.front(), a.back()) << "the picture should change as the vehicle drives";
}

TEST(RuntimeRender, FrameIsNotBlankAndTheFlagIsWhereItProjects) {
    const SceneConfig with = small("hanging_flag", 320, 240);
    SceneConfig without = with;
    without.subsystems &= ~(kCloth | kAir | kCollision);
    RunOptions o;
    o.frames = 30;
    Runtime a(with, o), b(without, o);
    while (a.frame() && b.frame()) {
    }
    const auto& pa = a.pixels();
    const auto& pb = b.pixels();
    ASSERT_EQ(pa.size(), 320u * 240 * 4);
    // Not blank: many distinct colours.
    std::vector<std::uint32_t> colours;
    for (std::size_t i = 0; i < pa.size(); i += 4 * 97) colours.push_back(pa[i] | pa[i + 1] << 8 | pa[i + 2] << 16);
    std::sort(colours.begin(), colours.end());
    EXPECT_GT(std::unique(colours.begin(), colours.end()) - colours.begin(), 50);

    // Project every particle with the scene's fixed camera, computed here independently, and
    // check that the picture differs from the flagless one there.
    const Eigen::Vector3d eye(with.camera.eye[0], with.camera.eye[1], with.camera.eye[2]);
    const Eigen::Vector3d target(with.camera.target[0], with.camera.target[1], with.camera.target[2]);
    const Eigen::Vector3d f = (target - eye).normalized();
    const Eigen::Vector3d r = f.cross(Eigen::Vector3d::UnitY()).normalized();
    const Eigen::Vector3d u = r.cross(f);
    const double t = std::tan(with.camera.fov * M_PI / 360.0), aspect = 320.0 / 240.0;
    const auto& x = a.flag()->state().x;
    int inside = 0, differs = 0;
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
        const Eigen::Vector3d d = x.col(i) - eye;
        const double px = (d.dot(r) / d.dot(f) / (t * aspect) * 0.5 + 0.5) * 320;
        const double py = (0.5 - d.dot(u) / d.dot(f) / t * 0.5) * 240;
        if (px < 1 || py < 1 || px >= 319 || py >= 239) continue;
        ++inside;
        const std::size_t k = (std::size_t(py) * 320 + std::size_t(px)) * 4;
        differs += std::abs(pa[k] - pb[k]) + std::abs(pa[k + 1] - pb[k + 1]) + std::abs(pa[k + 2] - pb[k + 2]) > 24;
    }
    ASSERT_GT(inside, int(x.cols()) / 2) << "the flag should be in view";
    EXPECT_GT(differs, inside * 8 / 10) << differs << " of " << inside << " projected particles show the flag";
}

TEST(RuntimeRender, ReplayingRecordedInputGivesTheSameFrames) {
    const std::string recorded = tempPath("flagsim_recorded_input.json");
    RunOptions rec;
    rec.frames = 60;
    rec.recordInput = recorded;
    const auto original = frameHashes(small("flag_vehicle"), rec);
    ASSERT_TRUE(std::filesystem::exists(recorded));
    RunOptions replay;
    replay.frames = 60;
    replay.scriptPath = recorded;
    EXPECT_EQ(frameHashes(small("flag_vehicle"), replay), original);
}

namespace {

std::vector<std::uint8_t> lastFrame(SceneConfig s, AntiAliasing aa, int scale) {
    s.render.aa = aa;
    s.render.msaa = 4;
    s.render.width *= scale;
    s.render.height *= scale;
    s.render.shadowMapSize *= scale;
    RunOptions o;
    o.frames = 20;
    Runtime rt(s, o);
    while (rt.frame()) {
    }
    return rt.pixels();
}

// The mean difference, in levels, between `frame` and the frame rendered at twice the size and
// averaged 2x2, over the edge channels: those whose 2x2 block spreads by more than 48 levels.
double edgeError(const std::vector<std::uint8_t>& frame, const std::vector<std::uint8_t>& big, int w, int h, int* edges) {
    double sum = 0;
    *edges = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                double mean = 0, lo = 255, hi = 0;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const double v = big[(std::size_t(2 * y + dy) * 2 * w + 2 * x + dx) * 4 + c];
                        mean += v / 4, lo = std::min(lo, v), hi = std::max(hi, v);
                    }
                if (hi - lo <= 48) continue;
                sum += std::abs(frame[(std::size_t(y) * w + x) * 4 + c] - mean);
                ++*edges;
            }
    return *edges ? sum / *edges : 0;
}

}  // namespace

// Anti-aliasing approximates supersampling where it matters, on edges: at the pixels whose 2x2
// block of the frame rendered at twice the size holds an edge, 4-sample multisampling and the
// post pass (frame_aa.h) are both much closer to the block's mean than the frame without either.
// The post pass's bound, 11 levels, is what the frame without it misses (about 14).
TEST(RuntimeRender, AntiAliasingIsCloseToTwiceTheResolutionAveragedOnEdges) {
    const SceneConfig s = small("hanging_flag", 320, 240);
    const auto big = lastFrame(s, AntiAliasing::Off, 2);
    int edges = 0;
    const double msaa = edgeError(lastFrame(s, AntiAliasing::Msaa, 1), big, 320, 240, &edges);
    const double post = edgeError(lastFrame(s, AntiAliasing::Post, 1), big, 320, 240, &edges);
    const double aliased = edgeError(lastFrame(s, AntiAliasing::Off, 1), big, 320, 240, &edges);
    ASSERT_GT(edges, 200) << "too few edges to judge";
    EXPECT_LT(msaa, 0.7 * aliased) << "mean difference on " << edges << " edge channels: msaa " << msaa << ", none " << aliased;
    EXPECT_LE(post, 11.0) << "post " << post << ", msaa " << msaa << ", none " << aliased;
    EXPECT_GT(aliased, 11.0) << "the bound must tell the pass from no pass";
}

// --overlay draws the panel into the recorded frames, in its own profile phase, and nowhere else:
// the frame matches the one without it outside the panel's corner, and differs inside it. (Without
// anti-aliasing: the post pass searches along an edge up to 24 pixels, so it blends the panel's
// border into the scene beside it.)
TEST(RuntimeRender, TheOverlayIsInItsOwnPhaseAndOnlyInThePanelsCorner) {
    SceneConfig s = small("flag_vehicle", 960, 540);
    s.render.aa = AntiAliasing::Off;
    RunOptions o;
    o.frames = 10;
    Runtime plain(s, o);
    o.overlay = true;
    Runtime overlay(s, o);
    while (plain.frame() && overlay.frame()) {
    }
    EXPECT_TRUE(overlay.profiler().enabled(Phase::Overlay));
    EXPECT_FALSE(plain.profiler().enabled(Phase::Overlay));
    const auto& a = plain.pixels();
    const auto& b = overlay.pixels();
    ASSERT_EQ(a.size(), b.size());
    std::size_t inside = 0, outside = 0;
    for (int y = 0; y < 540; ++y)
        for (int x = 0; x < 960; ++x) {
            const std::size_t i = (std::size_t(y) * 960 + x) * 4;
            const bool differs = a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2];
            (x < 8 + 330 + 2 ? inside : outside) += differs;
        }
    EXPECT_GT(inside, 20000u) << "the panel is not in the frame";
    EXPECT_EQ(outside, 0u) << "the overlay drew outside its corner";
}

// The post pass's frame, shown in a window, goes back into framebuffer 0 as it was made: a frame
// uploaded and read back again is the same, rows in the same order (a lost flip would mirror it).
TEST(Renderer, AFrameShownIsTheFrameReadBack) {
    std::string error;
    std::unique_ptr<GLContext> context = createOffscreenContext(64, 48, &error);
    ASSERT_TRUE(context) << error;
    Renderer renderer(*context, 256);
    std::vector<std::uint8_t> frame(64 * 48 * 4);
    for (std::size_t i = 0; i < frame.size(); ++i) frame[i] = std::uint8_t((i * 7 + i / 256) % 251);
    for (std::size_t i = 3; i < frame.size(); i += 4) frame[i] = 255;  // opaque: the buffer keeps alpha
    renderer.showPixels(frame);
    std::vector<std::uint8_t> back;
    renderer.readPixels(back);
    ASSERT_EQ(back.size(), frame.size());
    EXPECT_TRUE(back == frame);
}
