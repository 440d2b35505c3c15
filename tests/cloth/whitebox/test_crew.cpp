// small_steps' crew (small_steps/crew.h): thread 0 runs loops that another thread serves, session
// after session, as contact runs between two of the step's barriers. Every index of every loop is
// run exactly once, whichever thread gets there, when the server is there from the start, when
// it arrives after some loops or after the session has closed, and when it never comes (thread 0
// then takes every chunk). The two threads meet at a barrier between sessions, as the step's do.
// Thread 0 claims any chunk not yet started, so on a loaded machine the server may take none: in
// one loop thread 0 holds its chunk until the server has taken the other (up to 2 s), so that the
// server's part is tested too.

#include <gtest/gtest.h>

#include <atomic>
#include <barrier>
#include <chrono>
#include <thread>
#include <vector>

#include "small_steps/crew.h"

using namespace cloth;

TEST(Crew, EveryIndexOfEveryLoopRunsOnceWhenTheServerIsOnTimeLateOrAbsent) {
    constexpr std::uint32_t kSessions = 300;
    Crew crew(2);
    std::barrier meet(2);
    std::atomic<long> served{0};  // chunks the server ran
    std::thread server([&] {
        for (std::uint32_t s = 1; s <= kSessions; ++s) {
            if (s % 3 == 1) std::this_thread::sleep_for(std::chrono::microseconds(300));  // late: after loops, or after the close
            if (s % 7 != 0) crew.serve(s);                                                 // every seventh: never comes
            meet.arrive_and_wait();
        }
    });
    std::thread::id lead = std::this_thread::get_id();
    for (std::uint32_t s = 1; s <= kSessions; ++s) {
        crew.open(s);
        for (int loop = 0; loop < 5; ++loop) {
            const int n = int((s * 37 + std::uint32_t(loop) * 101) % 900);
            std::vector<int> hits(std::size_t(n), 0);
            const bool handshake = s == 2 && loop == 0;
            crew.run(n, [&](int begin, int end) {
                if (std::this_thread::get_id() != lead) served.fetch_add(1);
                const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
                while (handshake && served.load() == 0 && std::chrono::steady_clock::now() < until) std::this_thread::yield();
                for (int i = begin; i < end; ++i) ++hits[std::size_t(i)];
            });
            for (int i = 0; i < n; ++i) ASSERT_EQ(hits[std::size_t(i)], 1) << "session " << s << ", loop " << loop << ", index " << i;
        }
        crew.close();
        meet.arrive_and_wait();
    }
    server.join();
    EXPECT_GT(served.load(), 0) << "the server ran no chunk";
}
