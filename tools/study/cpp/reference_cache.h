#pragma once
// The front's references, computed once. Each reference run (its figures, and the states the
// trajectory errors restart from and compare against) is stored on disk under a key of everything
// that determines it, so that runs, shards and machines reuse it:
//   - the flag as the library steps it (its grid, size, mass, stiffness, solver, constraints,
//     drag, air, collisions, contact when the flag has any, substeps, rate) and its pole;
//   - the path: its name, duration, mass scale and wind, and its carrier sampled at every tick
//     (a changed path, the drive's Bullet run included, is another key);
//   - whether the states are kept;
//   - the code's version: the bits that the reference's integrator and the run's figures
//     compute on a small flag through a short, hard path, without contact and with it
//     (integratorVersion()), so that a change of the code that moves them is another key too.
// An entry holds its whole key and a checksum: one with another key, or truncated or corrupt, is
// refused and recomputed, never trusted. Entries are written to a temporary name and renamed, so
// that shards running at once never read half an entry.

#include <optional>
#include <string>

#include "extreme_runs.h"

namespace study {

struct CacheCounts {
    int reused = 0, computed = 0, refused = 0;
};

class ReferenceCache {
public:
    // An empty dir: no cache, every reference computed.
    explicit ReferenceCache(std::string dir = {});
    bool on() const { return !dir_.empty(); }
    // The run stored under `key`, or nothing (missing, another key, refused as corrupt).
    std::optional<ExtremeRun> load(const std::string& key);
    // Stores `run` under `key` (a failure to write is told on stderr once, not fatal).
    void store(const std::string& key, const ExtremeRun& run);
    // The reference for `key`: loaded, or computed by `compute` and stored.
    template <class Compute>
    ExtremeRun get(const std::string& key, Compute compute) {
        if (std::optional<ExtremeRun> r = load(key)) {
            ++counts_.reused;
            return std::move(*r);
        }
        ExtremeRun r = compute();
        ++counts_.computed;
        store(key, r);
        return r;
    }
    const CacheCounts& counts() const { return counts_; }
    std::string pathOf(const std::string& key) const;  // the entry's file

private:
    std::string dir_;
    CacheCounts counts_;
    bool warned_ = false;
};

// The key of a reference run of scene `s` on `mount` along path `x` (see above).
std::string referenceKey(const engine::SceneConfig& s, const engine::PoleMount& mount, const Extreme& x,
                         bool keepStates, const std::string& codeVersion);

// The code's version: a hash of what runExtreme computes (the figures and every state, bit for
// bit) for the reference's integrator on a 9x7 flag through 0.25 s of a hard path with the air,
// tethers, the stretch limit and the pole. Computed once per process.
const std::string& integratorVersion();

// 64-bit FNV-1a of bytes, from a running value.
std::uint64_t fnv1a(const void* data, std::size_t bytes, std::uint64_t h = 0xcbf29ce484222325ULL);

}  // namespace study
