// A host's task system (cloth/task_system.h) running the cloth's parallel work: the flag on two
// threads gives the bits of one thread whichever host runs the helpers (its own threads, inline,
// or only after the step), and a host that runs nothing until the step has returned holds the
// step up not at all: the calling thread takes every chunk. Tasks run after their cloth is gone
// do nothing (the sanitizer build would catch a freed region).

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "cloth/cloth.h"
#include "cloth/flag_on_pole.h"
#include "cloth/task_system.h"
#include "physics_support.h"

using namespace cloth;
using cloth::test::turningCarrier;

namespace {

// A host with threads of its own that run tasks as they come.
class ThreadHost final : public TaskSystem {
public:
    explicit ThreadHost(int threads) {
        for (int t = 0; t < threads; ++t) threads_.emplace_back([this] { loop(); });
    }
    ~ThreadHost() override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (auto& t : threads_) t.join();
    }
    void enqueue(std::function<void()> task) override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            tasks_.push_back(std::move(task));
        }
        ++enqueued;
        wake_.notify_one();
    }
    std::atomic<int> enqueued{0};

private:
    void loop() {
        for (;;) {
            std::function<void()> task;
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [this] { return stop_ || !tasks_.empty(); });
                if (tasks_.empty()) return;
                task = std::move(tasks_.front());
                tasks_.pop_front();
            }
            task();
        }
    }
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> tasks_;
    bool stop_ = false;
    std::vector<std::thread> threads_;
};

// A host that runs each task inside enqueue (a host without threads).
class InlineHost final : public TaskSystem {
public:
    void enqueue(std::function<void()> task) override { ++enqueued, task(); }
    int enqueued = 0;
};

// A host that keeps its tasks until drain(): as a game whose workers are all busy until the frame ends.
class DeferredHost final : public TaskSystem {
public:
    void enqueue(std::function<void()> task) override { tasks_.push_back(std::move(task)); }
    int drain() {
        const int n = int(tasks_.size());
        for (auto& task : tasks_) task();
        tasks_.clear();
        return n;
    }
    std::size_t pending() const { return tasks_.size(); }

private:
    std::vector<std::function<void()>> tasks_;
};

// The flag at side x side (17 unless given) on `solver`, in the wind on the turning carrier, with
// its pole, tethers, the stretch limit and contact: what the true-motion scene runs.
Cloth hostFlag(const std::string& solver, int side = 17) {
    FlagDesc f;
    f.nx = f.ny = side, f.onShell = true;
    ClothSettings s;
    std::string error;
    EXPECT_TRUE(parseSolverConfig(solver, s.solver, &error)) << error;
    s.air = true, s.airParams.wind = Vec3(4, 0, 1);
    s.collisions = true;
    s.constraints.tether = 0.1, s.constraints.stretchLimit = 0.1;
    s.contact.enabled = true;
    return Cloth(flagOnPole(f, Pole{}, s.thickness), s, turningCarrier(0));
}

constexpr int kHostTicks = 40;
constexpr double kTick = 1.0 / 240;

// The flag after kHostTicks, its host (if any) drained after every tick by `afterTick`.
State runFlag(const std::string& solver, TaskSystem* host, const std::function<void()>& afterTick = {}) {
    Cloth cloth = hostFlag(solver);
    cloth.setTaskSystem(host);
    for (int k = 1; k <= kHostTicks; ++k) {
        cloth.step(kTick, turningCarrier(k * kTick), {});
        if (afterTick) afterTick();
    }
    EXPECT_EQ(cloth.failures(), 0) << cloth.firstFailure();
    return cloth.state();
}

// small_steps' key that gives even this small cloth its threads (else it steps on one thread, and
// the threads' part goes untested).
std::string evenSmall(const std::string& solver) { return solver.rfind("small_steps", 0) == 0 ? ",parallel_from=0" : ""; }

void expectBitsOf(const State& a, const State& b) {
    EXPECT_TRUE(a.x == b.x);
    EXPECT_TRUE(a.v == b.v);
}

}  // namespace

TEST(TaskSystem, AHostsThreadsGiveTheBitsOfOneThread) {
    for (const char* solver : {"small_steps:max_move=0.01", "kangcho:precision=float"}) {
        SCOPED_TRACE(solver);
        const State one = runFlag(std::string(solver) + ",threads=1", nullptr);
        ThreadHost host(2);
        expectBitsOf(runFlag(std::string(solver) + ",threads=2" + evenSmall(solver), &host), one);
        EXPECT_GT(host.enqueued.load(), 0) << "the host ran none of the parallel work";
        InlineHost inlined;
        expectBitsOf(runFlag(std::string(solver) + ",threads=2" + evenSmall(solver), &inlined), one);
        EXPECT_GT(inlined.enqueued, 0);
    }
}

TEST(TaskSystem, AClothUnderParallelFromStepsOnOneThread) {
    // small_steps' default parallel_from is 2,048 particles: the 17x17 flag (289) on two threads
    // hands its host no task, with the bits of one thread; from parallel_from=289 it hands some.
    const State one = runFlag("small_steps:max_move=0.01,threads=1", nullptr);
    InlineHost small;
    expectBitsOf(runFlag("small_steps:max_move=0.01,threads=2", &small), one);
    EXPECT_EQ(small.enqueued, 0) << "a cloth under parallel_from handed its host work";
    InlineHost from;
    expectBitsOf(runFlag("small_steps:max_move=0.01,threads=2,parallel_from=289", &from), one);
    EXPECT_GT(from.enqueued, 0) << "a cloth of parallel_from particles stepped on one thread";
}

TEST(TaskSystem, AHostThatRunsNothingUntilTheStepEndsHoldsNothingUp) {
    // The host runs its tasks only after each tick: every step ends without them, on the
    // calling thread alone (a barrier that waited for them would never return), with the bits of
    // one thread; the tasks, run late, find nothing to do.
    const State one = runFlag("small_steps:max_move=0.01,threads=1", nullptr);
    DeferredHost host;
    int late = 0;
    const State two = runFlag("small_steps:max_move=0.01,threads=2,parallel_from=0", &host, [&] { late += host.drain(); });
    expectBitsOf(two, one);
    EXPECT_GT(late, 0);
}

TEST(TaskSystem, TasksRunAfterTheirClothIsGoneDoNothing) {
    DeferredHost host;
    {
        Cloth cloth = hostFlag("kangcho:precision=float,threads=2");
        cloth.setTaskSystem(&host);
        cloth.step(kTick, turningCarrier(kTick), {});
    }
    ASSERT_GT(host.pending(), 0u);
    host.drain();
}

TEST(TaskSystem, ContactOnTheStepsThreadsGivesTheBitsOfOneThread) {
    // At 65x65 small_steps' contact runs its loops on the step's threads (its other thread serving
    // them while thread 0 runs the contact, small_steps/crew.h): the pool's threads or a host's
    // give the bits of one thread, and the same primitives near the pole in every application (its
    // boxes made on both threads). The carrier spins the flag round its pole at 30 rad/s.
    auto spun = [](double t) {
        RigidFrame c;
        c.rotation = Eigen::AngleAxisd(30 * t, Vec3::UnitY());
        c.angularVelocity = Vec3(0, 30, 0);
        return c;
    };
    auto run = [&](const std::string& threads, TaskSystem* host) {
        Cloth cloth = hostFlag("small_steps:max_move=0.01,threads=" + threads, 65);
        cloth.setTaskSystem(host);
        for (int k = 1; k <= 12; ++k) cloth.step(kTick, spun(k * kTick), {});
        EXPECT_EQ(cloth.failures(), 0) << cloth.firstFailure();
        return std::pair{cloth.state(), cloth.contactTotal()};
    };
    const auto [one, r1] = run("1", nullptr);
    EXPECT_GT(r1.near, 10000);
    const auto [two, r2] = run("2", nullptr);
    expectBitsOf(two, one);
    EXPECT_EQ(r2.near, r1.near);
    ThreadHost host(1);
    const auto [hosted, r3] = run("2", &host);
    expectBitsOf(hosted, one);
    EXPECT_EQ(r3.near, r1.near);
}
