// NVIDIA Newton's solvers as a solver kind of the study, so that the front judges them as it
// judges every solver of this library: the same flags, paths, air and drag (as external forces,
// evaluated by the library at each step's start), the flag's tethers and stretch limit after the
// step (commitStep), restarts from the reference's states, contact with --contact. Each step sends
// the state, the pins' targets and the external force to a Python process
// (tools/study/flagstudy/nvidia_newton/bridge.py, its protocol there), which sets Newton's state
// to it and takes one Newton step on the CPU device. The profile's solve time is Newton's step as
// the process timed it (the front marks such rows' cost warp_cpu); the pipe is not counted.
// The Python is FLAGSIM_NVIDIA_NEWTON_PYTHON, else the project's venv (tools/run study
// --nvidia-newton makes it).

#include "nvidia_newton_kind.h"

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <stdexcept>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cloth/diagnostics.h"
#include "cloth/solver_kind.h"
#include "cloth/step_commit.h"
#include "peer_force.h"
#include "peer_process.h"

namespace study {

namespace {

struct NvidiaNewtonSettings {
    enum class Method { Vbd, Xpbd, Style3d } method = Method::Vbd;
    int iterations = 0;        // 0: Newton's default (VBD 10, XPBD 2, Style3D 10)
    int linearIterations = 0;  // Style3D's PCG iterations; 0: its default (10)
};

// The harness's spec of the settings (flagstudy/nvidia_newton/solvers.py).
std::string specOf(const NvidiaNewtonSettings& s) {
    using M = NvidiaNewtonSettings::Method;
    std::string spec = s.method == M::Vbd ? "vbd" : s.method == M::Xpbd ? "xpbd:substeps=1" : "style3d";
    auto add = [&](const char* key, int value) {
        if (value <= 0) return;
        spec.append(spec.find(':') == std::string::npos ? ":" : ",").append(key).append("=").append(std::to_string(value));
    };
    add("iterations", s.iterations);
    if (s.method == M::Style3d) add("linear_iterations", s.linearIterations);
    return spec;
}

std::string pythonPath() {
    if (const char* p = std::getenv("FLAGSIM_NVIDIA_NEWTON_PYTHON"); p && *p) return p;
    return FLAGSIM_SOURCE_DIR "/.venv-nvidia-newton/bin/python";
}

constexpr const char* kVenvHint =
    " (NVIDIA Newton's venv: tools/run study --nvidia-newton makes it; FLAGSIM_NVIDIA_NEWTON_PYTHON names another Python)";

// The bridge's process, or an error that says where the Python comes from.
std::unique_ptr<PeerProcess> launch() {
    try {
        return std::make_unique<PeerProcess>(std::vector<std::string>{pythonPath(), "-m", "flagstudy.nvidia_newton.bridge"},
                                             std::vector<std::string>{"PYTHONPATH=" FLAGSIM_SOURCE_DIR "/tools/study"});
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(std::string(e.what()) + kVenvHint);
    }
}

// The process and its flag: the model and the pinned particles it was opened with.
class Peer {
public:
    Peer(const cloth::Model& m, const cloth::Environment& env, const std::vector<cloth::Pin>& pins, const std::string& spec)
        : process_(launch()), model_(m.id()) {
        nlohmann::json j;
        j["solver"] = spec;
        j["size"] = m.gridNx();
        j["gravity"] = {env.gravity.x(), env.gravity.y(), env.gravity.z()};
        for (cloth::Index i = 0; i < m.particleCount(); ++i) {
            const cloth::Vec3 x = m.restPositions().col(i);
            j["rest_positions"].push_back({x.x(), x.y(), x.z()});
            j["masses"].push_back(m.masses()[i]);
        }
        for (const cloth::Spring& sp : m.springs()) j["springs"].push_back({sp.i, sp.j, sp.k, sp.rest, cloth::toString(sp.kind)});
        for (const cloth::Triangle& t : m.triangles()) j["triangles"].push_back({t[0], t[1], t[2]});
        for (const cloth::Pin& p : pins) j["pinned"].push_back(p.particle), pinned_.push_back(p.particle);
        const std::string line = j.dump() + "\n";
        process_->write(line.data(), line.size());
        answer();
    }
    ~Peer() {
        try {
            const std::int32_t quit = 0;
            process_->write(&quit, sizeof quit);
        } catch (const std::exception&) {  // already gone
        }
    }

    bool fits(const cloth::Model& m, const std::vector<cloth::Pin>& pins) const {
        if (m.id() != model_ || pins.size() != pinned_.size()) return false;
        for (std::size_t k = 0; k < pins.size(); ++k)
            if (pins[k].particle != pinned_[k]) return false;
        return true;
    }

    // One Newton step of h from `state` into `out`; returns Newton's milliseconds.
    double step(double h, const cloth::State& state, const std::vector<cloth::Pin>& pins, const cloth::Points& force,
                cloth::State& out) {
        const std::int32_t op = 1;
        process_->write(&op, sizeof op);
        process_->write(&h, sizeof h);
        send(state.x), send(state.v);
        for (const cloth::Pin& p : pins) process_->write(p.x.data(), 3 * sizeof(double));
        send(force);
        answer();
        double ms = 0;
        process_->read(&ms, sizeof ms);
        out.x.resize(3, state.x.cols()), out.v.resize(3, state.v.cols());
        process_->read(out.x.data(), std::size_t(out.x.size()) * sizeof(double));
        process_->read(out.v.data(), std::size_t(out.v.size()) * sizeof(double));
        return ms;
    }

private:
    void send(const cloth::Points& p) { process_->write(p.data(), std::size_t(p.size()) * sizeof(double)); }
    // The answer's status: 0, or 1 and the reason, thrown.
    void answer() {
        std::int32_t status = 0;
        process_->read(&status, sizeof status);
        if (status == 0) return;
        std::int32_t length = 0;
        process_->read(&length, sizeof length);
        std::string why(std::size_t(std::max(0, length)), ' ');
        process_->read(why.data(), why.size());
        throw std::runtime_error("nvidia_newton: " + why);
    }

    std::unique_ptr<PeerProcess> process_;
    std::uint64_t model_;
    std::vector<cloth::Index> pinned_;
};

class NvidiaNewtonSolver final : public cloth::Solver {
public:
    cloth::StepResult step(const cloth::Model& model, const cloth::Environment& env, cloth::State& state,
                           const cloth::StepInput& input) override {
        using namespace cloth;
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        if (!peer_ || !peer_->fits(model, input.pins))
            peer_.reset(), peer_ = std::make_unique<Peer>(model, env, input.pins, specOf(settings<NvidiaNewtonSettings>()));
        peerForce(model, env, state, input, force_);  // gravity is Newton's own (the model's, from env)
        for (const Pin& p : input.pins) force_.col(p.particle).setZero();  // as the harness gives it
        const double newtonMs = peer_->step(input.h, state, input.pins, force_, scratch_);
        dv_ = scratch_.v - state.v;
        const auto t0 = std::chrono::steady_clock::now();
        StepResult r = commitStep(model, constraints_, input, *pool_, state, scratch_, StepResult{});
        profile_ = {0, newtonMs, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()};
        r.iterations = settings<NvidiaNewtonSettings>().iterations;
        return r;
    }

private:
    std::unique_ptr<Peer> peer_;
    cloth::State scratch_;
    cloth::Points force_;
};

}  // namespace

std::string nvidiaNewtonUnavailable() {
    const std::string python = pythonPath();
    if (access(python.c_str(), X_OK) == 0) return {};
    return "nvidia_newton: no Python at '" + python + "'" + kVenvHint;
}

void registerNvidiaNewton() {
    using namespace cloth;
    if (findSolverKind("nvidia_newton")) return;
    using N = NvidiaNewtonSettings;
    using key = SolverKeys;
    registerSolverKind(
        {"nvidia_newton",
         "NVIDIA Newton's VBD, XPBD or Style3D (a study peer, in the project's Newton venv): one Newton step per step",
         defaultsTo<N>,
         withCommon({key::shown(key::choice("method", &N::method,
                                            {{"vbd", N::Method::Vbd}, {"xpbd", N::Method::Xpbd}, {"style3d", N::Method::Style3d}},
                                            "Newton's solver")),
                     key::integer("iterations", &N::iterations, 0, 10000, "its iterations per step (0: Newton's default)"),
                     key::integer("linear_iterations", &N::linearIterations, 0, 10000,
                                  "style3d: PCG iterations per iteration (0: its default)")},
                    false),
         {},
         createSolver<NvidiaNewtonSolver>});
}

}  // namespace study
