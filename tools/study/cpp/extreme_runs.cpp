#include "extreme_runs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "cloth/crossings.h"
#include "cloth/diagnostics.h"

namespace study {

namespace {

using Clock = std::chrono::steady_clock;

double mean(const std::vector<double>& v, std::size_t begin, std::size_t end) {
    double s = 0;
    for (std::size_t k = begin; k < end; ++k) s += v[k];
    return end > begin ? s / double(end - begin) : NAN;
}

// The figures of one tick into the run's maxima.
void record(ExtremeRun& r, const cloth::Diagnostics& d, const cloth::Cloth& flag, const engine::RigidFrame& c,
            const Extreme& x, double t) {
    r.maxStretch = std::max(r.maxStretch, d.maxStretch);
    if (!(x.jumpAt >= 0 && t >= x.jumpAt && t < x.jumpAt + 0.25)) r.peakStretch = std::max(r.peakStretch, d.maxStretch);
    r.p99Stretch = std::max(r.p99Stretch, d.p99Stretch);
    if (t > x.duration - 1) r.lateStretch = std::max(r.lateStretch, d.maxStretch);
    for (cloth::Index i = 0; i < flag.model().particleCount(); ++i)
        r.maxSpeed = std::max(r.maxSpeed, (flag.state().v.col(i) - c.linearVelocity).norm());
}

// The crossings of the flag's state on carrier c: edges through the pole's solid (on its axis, the
// pinned column's edges are its sleeve and are left out), and through the flag itself.
int crossingsOf(const cloth::Cloth& flag, const engine::PoleMount& mount, const engine::RigidFrame& c, bool onAxis) {
    cloth::CrossingScene scene;
    const auto [a, b] = cloth::poleAxis(mount);
    scene.capsules.push_back({c.point(a), c.point(b), mount.radius});
    std::vector<std::uint8_t> sleeve;
    if (onAxis) {
        sleeve.assign(std::size_t(flag.model().particleCount()), 0);
        for (const cloth::Pin& p : flag.pins()) sleeve[std::size_t(p.particle)] = 1;
    }
    return cloth::countCrossings(flag.model(), flag.state().x, scene, onAxis ? &sleeve : nullptr).total();
}

}  // namespace

double carrierEnergy(const cloth::Model& m, const cloth::State& s, const engine::RigidFrame& c) {
    double e = 0;
    for (cloth::Index i = 0; i < m.particleCount(); ++i)
        e += 0.5 * m.masses()[i] * (s.v.col(i) - c.velocityAt(s.x.col(i))).squaredNorm();
    return e;
}

double patchEnergy(const cloth::Model& m, const cloth::State& s, const engine::RigidFrame& c, int patches) {
    const int nx = m.gridNx(), ny = m.gridNy();
    if (patches < 1 || nx < patches || ny < patches) return NAN;
    std::vector<double> mass(patches * patches, 0.0);
    std::vector<Eigen::Vector3d> momentum(patches * patches, Eigen::Vector3d::Zero());
    for (int r = 0; r < ny; ++r)
        for (int col = 0; col < nx; ++col) {
            const cloth::Index i = cloth::Index(r) * nx + col;
            const int patch = (r * patches / ny) * patches + col * patches / nx;
            mass[patch] += m.masses()[i];
            momentum[patch] += m.masses()[i] * (s.v.col(i) - c.velocityAt(s.x.col(i)));
        }
    double e = 0;
    for (int p = 0; p < patches * patches; ++p) e += 0.5 * momentum[p].squaredNorm() / mass[p];
    return e;
}

ExtremeRun runExtreme(const engine::SceneConfig& s, const engine::PoleMount& mount, const Extreme& x, bool keepStates) {
    cloth::Cloth flag = engine::makeFlagCloth(s, mount, x.carrier(0));
    const double h = 1.0 / s.physicsHz;
    ExtremeRun r;
    std::vector<double> tickMs, profiledMs, energy;
    std::array<std::vector<double>, kPatchCounts.size()> patch;
    if (keepStates) r.states.push_back(flag.state());
    const int ticks = int(std::floor(x.duration / h + 1e-9));
    for (int k = 1; k <= ticks; ++k) {
        const engine::RigidFrame c = x.carrier(k * h);
        const auto t0 = Clock::now();
        flag.step(h, c, {cloth::poleCollider(mount, c)});
        tickMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        const cloth::ClothProfile& p = flag.profile();
        profiledMs.push_back(p.air + p.forces + p.solve + p.collision + p.contact);
        const cloth::Diagnostics d = cloth::measure(flag.model(), {}, flag.state(), true);
        record(r, d, flag, c, x, k * h);
        energy.push_back(carrierEnergy(flag.model(), flag.state(), c));
        for (std::size_t p = 0; p < kPatchCounts.size(); ++p)
            patch[p].push_back(patchEnergy(flag.model(), flag.state(), c, kPatchCounts[p]));
        if (keepStates) r.states.push_back(flag.state());
        const int crossings = crossingsOf(flag, mount, c, !engine::flagDescOf(s).onShell);
        r.crossingsMax = std::max(r.crossingsMax, crossings);
        r.crossingTicks += crossings > 0;
        // Stable (extreme_runs.h): finite and bounded; stretch is judged by the bounds instead.
        cloth::StabilityLimits limits;
        limits.maxStretch = std::numeric_limits<double>::infinity();
        if (cloth::instability(d, flag.state(), c.point(Eigen::Vector3d(0, mount.height, 0)), limits)) r.stable = false;
    }
    r.stable = r.stable && flag.failures() == 0;
    r.failures = flag.failures(), r.firstFailure = flag.firstFailure();
    std::nth_element(tickMs.begin(), tickMs.begin() + tickMs.size() / 2, tickMs.end());
    r.msPerTick = tickMs[tickMs.size() / 2];
    std::nth_element(profiledMs.begin(), profiledMs.begin() + profiledMs.size() / 2, profiledMs.end());
    r.msPerTickProfiled = profiledMs[profiledMs.size() / 2];
    const std::size_t perWindow = std::size_t(std::lround(kEnergyWindow / h)), perSecond = std::size_t(std::lround(1 / h));
    const auto lastSecond = [perSecond](const std::vector<double>& v) {
        return mean(v, v.size() - std::min(v.size(), perSecond), v.size());
    };
    r.energyMean = mean(energy, 0, energy.size());
    r.energyLate = lastSecond(energy);
    for (std::size_t p = 0; p < kPatchCounts.size(); ++p) r.patchEnergyLate[p] = lastSecond(patch[p]);
    for (std::size_t w = 0; w < energy.size(); w += perWindow)
        r.energyWindows.push_back(mean(energy, w, std::min(energy.size(), w + perWindow)));
    const long long steps = std::max(1LL, flag.steps());
    r.iterationsMean = double(flag.counts().iterations) / double(steps);
    r.iterationsMax = flag.counts().maxIterations;
    return r;
}

int referenceSubsteps(int base, int size, const Extreme& x, const std::vector<Eigen::Vector3d>& pins) {
    const int stability = int(std::ceil(base * (size / 33.0) / std::sqrt(x.massScale)));
    if (pins.empty()) return stability;
    const double h = 1 / kReferenceHz, tickMove = pinMotion(x.carrier, x.duration, h, pins).speedMax * h;
    return std::max(stability, int(std::ceil(tickMove / kReferencePinStep - 1e-9)));
}

engine::SceneConfig referenceScene(engine::SceneConfig s, int substeps, bool springsOnly) {
    cloth::SolverConfig explicitEuler;
    std::string error;
    cloth::parseSolverConfig("explicit:substeps=1", explicitEuler, &error);
    s.flag.solver = explicitEuler;
    if (springsOnly) s.flag.constraints = {};
    s.flag.substeps = substeps;
    s.flag.implicitAir = false;  // explicit: the air's Jacobian would go unused
    s.physicsHz = kReferenceHz;  // its substeps are per 240 Hz tick, whatever the scene's rate
    return s;
}

double horizonError(const engine::SceneConfig& s, const engine::PoleMount& mount, const Extreme& x,
                    const std::vector<cloth::State>& reference, double referenceH) {
    const double h = 1.0 / s.physicsHz;
    const int every = int(std::lround(h / referenceH));  // reference ticks per tick
    if (every < 1 || std::abs(every * referenceH - h) > 1e-9 * h) return NAN;
    const int horizon = std::max(1, int(std::lround(kHorizon / h)));
    cloth::Cloth flag = engine::makeFlagCloth(s, mount, x.carrier(0));
    double sum = 0;
    long count = 0;
    for (std::size_t start = 0; start + std::size_t(horizon * every) < reference.size(); start += std::size_t(horizon * every)) {
        flag.restart(reference[start], x.carrier(double(start) * referenceH));
        for (int k = 1; k <= horizon; ++k) {
            const std::size_t at = start + std::size_t(k * every);
            const engine::RigidFrame c = x.carrier(double(at) * referenceH);
            flag.step(h, c, {cloth::poleCollider(mount, c)});
            sum += (flag.state().x - reference[at].x).colwise().squaredNorm().mean();
            ++count;
        }
    }
    if (flag.failures() > 0 || !std::isfinite(sum)) return NAN;
    return count ? std::sqrt(sum / double(count)) / s.flag.width : NAN;
}

}  // namespace study
