#include "reference_cache.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <unistd.h>

namespace study {

namespace {

constexpr char kMagic[] = "flagsim reference 2\n";
// Velocities are kept where a trajectory error restarts (every kHorizon); positions at every tick.
const long kRestartEvery = std::lround(kHorizon * kReferenceHz);

// Bytes appended to a buffer, and read back from one with bounds checked.
struct Writer {
    std::string bytes;
    template <class T>
    void put(const T& v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
    void put(const double* p, std::size_t n) { bytes.append(reinterpret_cast<const char*>(p), n * sizeof(double)); }
};

struct Reader {
    const std::string& bytes;
    std::size_t at = 0;
    bool ok = true;
    template <class T>
    T get() {
        T v{};
        read(&v, sizeof v);
        return v;
    }
    void read(void* out, std::size_t n) {
        if (!ok || bytes.size() - at < n) {
            ok = false;
            return;
        }
        std::memcpy(out, bytes.data() + at, n);
        at += n;
    }
};

void putRun(Writer& w, const ExtremeRun& r) {
    w.put(std::uint8_t(r.stable));
    w.put(std::int32_t(r.failures));
    for (double v : {r.msPerTick, r.maxStretch, r.peakStretch, r.p99Stretch, r.lateStretch, r.maxSpeed, r.energyMean,
                     r.energyLate, r.patchEnergyLate[0], r.patchEnergyLate[1], r.patchEnergyLate[2], r.iterationsMean})
        w.put(v);
    w.put(std::int32_t(r.iterationsMax));
    w.put(std::int32_t(r.crossingsMax)), w.put(std::int32_t(r.crossingTicks));
    w.put(std::uint64_t(r.energyWindows.size()));
    w.put(r.energyWindows.data(), r.energyWindows.size());
    const std::uint64_t n = r.states.empty() ? 0 : std::uint64_t(r.states.front().x.cols());
    w.put(std::uint64_t(r.states.size()));
    w.put(n);
    for (std::size_t k = 0; k < r.states.size(); ++k) {
        w.put(r.states[k].x.data(), 3 * n);
        if (long(k) % kRestartEvery == 0) w.put(r.states[k].v.data(), 3 * n);
    }
}

bool getRun(Reader& in, ExtremeRun& r) {
    r.stable = in.get<std::uint8_t>() != 0;
    r.failures = in.get<std::int32_t>();
    for (double* v : {&r.msPerTick, &r.maxStretch, &r.peakStretch, &r.p99Stretch, &r.lateStretch, &r.maxSpeed,
                      &r.energyMean, &r.energyLate, &r.patchEnergyLate[0], &r.patchEnergyLate[1], &r.patchEnergyLate[2],
                      &r.iterationsMean})
        *v = in.get<double>();
    r.iterationsMax = in.get<std::int32_t>();
    r.crossingsMax = in.get<std::int32_t>(), r.crossingTicks = in.get<std::int32_t>();
    const auto windows = in.get<std::uint64_t>();
    if (!in.ok || windows > 1'000'000) return false;
    r.energyWindows.resize(windows);
    in.read(r.energyWindows.data(), windows * sizeof(double));
    const auto states = in.get<std::uint64_t>(), n = in.get<std::uint64_t>();
    if (!in.ok || states > 10'000'000 || n > 10'000'000) return false;
    r.states.resize(states);
    for (std::size_t k = 0; k < states && in.ok; ++k) {
        cloth::State& s = r.states[k];
        s.x.resize(3, Eigen::Index(n));
        s.v.setConstant(3, Eigen::Index(n), NAN);  // not kept here: no restart reads it
        in.read(s.x.data(), 3 * n * sizeof(double));
        if (long(k) % kRestartEvery == 0) in.read(s.v.data(), 3 * n * sizeof(double));
    }
    return in.ok;
}

std::string readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return {};
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

}  // namespace

std::uint64_t fnv1a(const void* data, std::size_t bytes, std::uint64_t h) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
    return h;
}

ReferenceCache::ReferenceCache(std::string dir) : dir_(std::move(dir)) {}

std::string ReferenceCache::pathOf(const std::string& key) const {
    char name[40];
    std::snprintf(name, sizeof name, "%016llx.ref", static_cast<unsigned long long>(fnv1a(key.data(), key.size())));
    return dir_ + "/" + name;
}

std::optional<ExtremeRun> ReferenceCache::load(const std::string& key) {
    if (!on()) return std::nullopt;
    const std::string bytes = readFile(pathOf(key));
    if (bytes.empty()) return std::nullopt;  // missing
    // magic, key, run, then the checksum of all that precedes it
    const std::size_t body = bytes.size() >= 8 ? bytes.size() - 8 : 0;
    std::uint64_t sum = 0;
    if (body > 0) std::memcpy(&sum, bytes.data() + body, 8);
    const std::string head = std::string(kMagic) + key;
    ExtremeRun r;
    Reader in{bytes};
    in.at = head.size() + 8;
    std::uint64_t keyBytes = 0;
    if (bytes.size() >= std::strlen(kMagic) + 8) std::memcpy(&keyBytes, bytes.data() + std::strlen(kMagic), 8);
    const bool valid = body >= in.at && sum == fnv1a(bytes.data(), body) && bytes.compare(0, std::strlen(kMagic), kMagic) == 0;
    const bool sameKey = valid && keyBytes == key.size() && bytes.compare(std::strlen(kMagic) + 8, key.size(), key) == 0;
    if (!sameKey || !getRun(in, r) || in.at != body) {
        ++counts_.refused;
        return std::nullopt;
    }
    return r;
}

void ReferenceCache::store(const std::string& key, const ExtremeRun& run) {
    if (!on()) return;
    Writer w;
    w.bytes = kMagic;
    w.put(std::uint64_t(key.size()));
    w.bytes += key;
    putRun(w, run);
    w.put(fnv1a(w.bytes.data(), w.bytes.size()));
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    const std::string path = pathOf(key), part = path + ".part" + std::to_string(::getpid());
    std::ofstream f(part, std::ios::binary);
    f.write(w.bytes.data(), std::streamsize(w.bytes.size()));
    f.close();
    if (f && !std::rename(part.c_str(), path.c_str())) return;
    std::remove(part.c_str());
    if (!warned_) std::fprintf(stderr, "cloth_study: cannot write the reference cache in %s\n", dir_.c_str());
    warned_ = true;
}

}  // namespace study
