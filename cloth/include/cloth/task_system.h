#pragma once
// A host's task system: a game that runs its own job system (as Jolt's JobSystem and Box2D v3's
// enqueueTask let it) runs the cloth's parallel work on its threads instead of the library's
// (Cloth::setTaskSystem, ThreadPool::useHost). The library still splits every parallel loop
// itself, by the loop's size and the solver's threads= alone, so the host never changes a bit. It
// hands the host helper tasks, one per chunk after the first: a helper claims whichever chunks are
// left and returns. The calling thread claims chunks too and waits only for chunks a helper has
// begun, so a task the host runs late, or only after the step, holds nothing up (it then finds
// no chunk left and returns at once).

#include <functional>

namespace cloth {

class TaskSystem {
public:
    virtual ~TaskSystem() = default;
    // Runs `task` once, on any thread (inside enqueue too: a host without threads), now or
    // later; the host may copy it. A task that runs after the loop, or the pool, that enqueued it
    // is gone finds nothing to do.
    virtual void enqueue(std::function<void()> task) = 0;
};

}  // namespace cloth
