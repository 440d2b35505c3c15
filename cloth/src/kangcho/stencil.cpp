#include "kangcho/stencil.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "kernels.h"
#include "pack.h"

namespace cloth {

std::vector<int> springFamilies(const Model& model) {
    std::map<int, std::set<int>> lowEnds;  // offset -> lower ends
    for (const Spring& s : model.springs()) {
        const int lo = int(std::min(s.i, s.j)), d = int(std::max(s.i, s.j)) - lo;
        if (d == 0 || !lowEnds[d].insert(lo).second) return {};  // a self-spring or a duplicate
        if (lowEnds.size() > std::size_t(kMaxFamilies)) return {};
    }
    std::vector<int> offsets;
    for (const auto& [d, ends] : lowEnds) offsets.push_back(d);
    const long long slots = (long long)offsets.size() * model.particleCount();
    if (offsets.empty() || slots > 2LL * model.springCount()) return {};
    return offsets;
}

namespace {

// One family's per-slot arrays as the kernels see them: the spring's direction u, its Jacobian's a
// and b (J = a I + b u u^T), and its force magnitude fm (the force on the lower end is fm u).
template <class T>
struct FamilyView {
    T *ux, *uy, *uz, *a, *b, *fm;
    int d;
};

template <class T, class Family>
FamilyView<T> viewOf(Family& F, int pad, int d) {
    return {F.ux.at(pad), F.uy.at(pad), F.uz.at(pad), F.a.at(pad), F.b.at(pad), F.fm.at(pad), d};
}

// J q for a spring's Jacobian J = a I + b u u^T, accumulated into (sx, sy, sz).
template <class T>
CLOTH_INLINE inline void addJacobianTimes(T a, T b, T ux, T uy, T uz, T qx, T qy, T qz, T& sx, T& sy, T& sz) {
    const T uq = b * (ux * qx + uy * qy + uz * qz);
    sx += a * qx + uq * ux;
    sy += a * qy + uq * uy;
    sz += a * qz + uq * uz;
}

// Eqs. 15-17 for one family's slots [begin, end): u, a, b and the force magnitude.
template <class T>
CLOTH_SIMD_CLONES void springKernel(const T* __restrict x, const T* __restrict y, const T* __restrict z,
                                    const T* __restrict k, const T* __restrict rest, bool compressionRule,
                                    const FamilyView<T>& out, int begin, int end) {
    const int d = out.d;
    T *__restrict ux = out.ux, *__restrict uy = out.uy, *__restrict uz = out.uz, *__restrict a = out.a;
    T *__restrict b = out.b, *__restrict fm = out.fm;
CLOTH_IVDEP
    for (int p = begin; p < end; ++p) {
        const SpringTerms<T> t =
            springTerms(x[p + d] - x[p], y[p + d] - y[p], z[p + d] - z[p], k[p], rest[p], compressionRule);
        ux[p] = t.ux, uy[p] = t.uy, uz[p] = t.uz, a[p] = t.a, b[p] = t.b, fm[p] = t.fm;
    }
}

// The particle passes walk their range in packs of lanes (pack.h): per pack, each family and each
// end of its springs adds into accumulators held in registers, in the same order for every lane.
// A spring is seen from its lower end (slot i, other end i + d, u pointing away: sign +1) and
// from its upper end (slot i - d, other end i - d, sign -1). The range's last few particles run
// the same code on scalars (V = T), with the same bits.

// One end of a family's springs as particle i sees it: the family's arrays shifted so that
// particle i's slot is at [i] (by 0 from the lower end, by -d from the upper), the offset of the
// other end (+d or -d) and the sign of the force (+1 or -1). solve() lists the lower and the upper
// end of each family in turn, the order of the sums.
template <class T>
struct SpringSide {
    const T *ux, *uy, *uz, *a, *b, *fm;
    int other;
    T sign;
};

template <class T>
struct ParticleArgs {
    const SpringSide<T>* sides;
    int sideCount;
    const T *vx, *vy, *vz, *wx, *wy, *wz, *f0x, *f0y, *f0z, *pinned, *mass;
    const T* damp[6];  // h C_i of the external force (xx xy xz yy yz zz), zero when explicit
    T *rx, *ry, *rz, *w0, *w1, *w2, *w3, *w4, *w5, *dx, *dy, *dz;
    T h, c;
};

// What the springs give particles i...: f = f0 + sum of spring forces, K = A I + B the sum of
// their Jacobian blocks (eq. 12 without its mass and h^2), and j = sum_j J_ij w_j.
template <class V>
struct SpringSums {
    V fx, fy, fz, A, Bxx, Bxy, Bxz, Byy, Byz, Bzz, jx, jy, jz;
};

template <class T, class V>
CLOTH_INLINE inline SpringSums<V> springSums(const ParticleArgs<T>& args, int i) {
    SpringSums<V> s{};
    s.fx = load<V>(args.f0x + i), s.fy = load<V>(args.f0y + i), s.fz = load<V>(args.f0z + i);
    for (int k = 0; k < args.sideCount; ++k) {
        const SpringSide<T>& S = args.sides[k];
        const int j = i + S.other;
        const V x = load<V>(S.ux + i), y = load<V>(S.uy + i), z = load<V>(S.uz + i);
        const V a = load<V>(S.a + i), b = load<V>(S.b + i);
        const V fs = S.sign * load<V>(S.fm + i);
        s.fx += fs * x, s.fy += fs * y, s.fz += fs * z;
        s.A += a;
        s.Bxx += b * x * x, s.Bxy += b * x * y, s.Bxz += b * x * z;
        s.Byy += b * y * y, s.Byz += b * y * z, s.Bzz += b * z * z;
        addJacobianTimes(a, b, x, y, z, load<V>(args.wx + j), load<V>(args.wy + j), load<V>(args.wz + j), s.jx, s.jy,
                         s.jz);
    }
    return s;
}

// Per particle: f, W_ii (eq. 12), b_i (eq. 7, pinned columns moved to the right), W_ii^-1 and
// dv(0) = W_ii^-1 b_i (eq. 11). The b_i term sum_j J_ij (w_j - v_i) is computed as
// sum_j J_ij w_j - (A I + B) v_i; w = v + the prescribed dv of pinned particles (v elsewhere)
// carries the pinned columns. Pinned particles get dv = 0 here: their prescribed dv is already in
// their neighbours' b_i, and solve() writes it into the result.
template <class T, class V>
CLOTH_INLINE inline void particleLanes(const ParticleArgs<T>& args, int i) {
    const T h = args.h, h2 = h * h;
    const SpringSums<V> s = springSums<T, V>(args, i);
    const V vx = load<V>(args.vx + i), vy = load<V>(args.vy + i), vz = load<V>(args.vz + i);
    // sum_j J_ij (w_j - v_i) = sum_j J_ij w_j - (A I + B) v_i
    const V kxx = s.A + s.Bxx, kxy = s.Bxy, kxz = s.Bxz, kyy = s.A + s.Byy, kyz = s.Byz, kzz = s.A + s.Bzz;
    const V ex = s.jx - (kxx * vx + kxy * vy + kxz * vz);
    const V ey = s.jy - (kxy * vx + kyy * vy + kyz * vz);
    const V ez = s.jz - (kxz * vx + kyz * vy + kzz * vz);
    const V r0 = h * s.fx + h2 * ex, r1 = h * s.fy + h2 * ey, r2 = h * s.fz + h2 * ez;
    // W = m (1 + h c) I + h C + h^2 (A I + B), as 6 numbers, and its inverse.
    const V diag = load<V>(args.mass + i) * (T(1) + h * args.c);
    const V W[6] = {diag + load<V>(args.damp[0] + i) + h2 * kxx, load<V>(args.damp[1] + i) + h2 * kxy,
                    load<V>(args.damp[2] + i) + h2 * kxz,        diag + load<V>(args.damp[3] + i) + h2 * kyy,
                    load<V>(args.damp[4] + i) + h2 * kyz,        diag + load<V>(args.damp[5] + i) + h2 * kzz};
    V inv[6];
    symmetricInverse<V, T>(W, inv);
    store(args.rx + i, r0), store(args.ry + i, r1), store(args.rz + i, r2);
    T* const out[6] = {args.w0, args.w1, args.w2, args.w3, args.w4, args.w5};
    for (int e = 0; e < 6; ++e) store(out[e] + i, inv[e]);
    const auto free = load<V>(args.pinned + i) == T(0);
    const V zero{};
    store(args.dx + i, free ? inv[0] * r0 + inv[1] * r1 + inv[2] * r2 : zero);
    store(args.dy + i, free ? inv[1] * r0 + inv[3] * r1 + inv[4] * r2 : zero);
    store(args.dz + i, free ? inv[2] * r0 + inv[4] * r1 + inv[5] * r2 : zero);
}

template <class T>
CLOTH_SIMD_CLONES void particleKernel(const ParticleArgs<T>& args, int begin, int end) {
    int i = begin;
    for (; i + kLanes<T> <= end; i += kLanes<T>) particleLanes<T, Pack<T>>(args, i);
    for (; i < end; ++i) particleLanes<T, T>(args, i);
}

template <class T>
struct SweepArgs {
    const SpringSide<T>* sides;
    int sideCount;
    const T *rx, *ry, *rz, *w0, *w1, *w2, *w3, *w4, *w5, *pinned, *inx, *iny, *inz;
    T *outx, *outy, *outz;
    T h2;
};

// One Jacobi sweep (eq. 11; from dv(0) it is eq. 14): dv_i = W_ii^-1 (b_i + h^2 sum_j J dv_j).
// Pinned particles hold dv = 0, so their columns (already in b_i) add nothing.
template <class T, class V>
CLOTH_INLINE inline void sweepLanes(const SweepArgs<T>& args, int i) {
    V sx{}, sy{}, sz{};
    for (int k = 0; k < args.sideCount; ++k) {
        const SpringSide<T>& S = args.sides[k];
        const int j = i + S.other;
        addJacobianTimes(load<V>(S.a + i), load<V>(S.b + i), load<V>(S.ux + i), load<V>(S.uy + i), load<V>(S.uz + i),
                         load<V>(args.inx + j), load<V>(args.iny + j), load<V>(args.inz + j), sx, sy, sz);
    }
    const T h2 = args.h2;
    const V y0 = load<V>(args.rx + i) + h2 * sx, y1 = load<V>(args.ry + i) + h2 * sy, y2 = load<V>(args.rz + i) + h2 * sz;
    const V w0 = load<V>(args.w0 + i), w1 = load<V>(args.w1 + i), w2 = load<V>(args.w2 + i);
    const V w3 = load<V>(args.w3 + i), w4 = load<V>(args.w4 + i), w5 = load<V>(args.w5 + i);
    const auto free = load<V>(args.pinned + i) == T(0);
    const V zero{};
    store(args.outx + i, free ? w0 * y0 + w1 * y1 + w2 * y2 : zero);
    store(args.outy + i, free ? w1 * y0 + w3 * y1 + w4 * y2 : zero);
    store(args.outz + i, free ? w2 * y0 + w4 * y1 + w5 * y2 : zero);
}

template <class T>
CLOTH_SIMD_CLONES void sweepKernel(const SweepArgs<T>& args, int begin, int end) {
    int i = begin;
    for (; i + kLanes<T> <= end; i += kLanes<T>) sweepLanes<T, Pack<T>>(args, i);
    for (; i < end; ++i) sweepLanes<T, T>(args, i);
}

// Structure of arrays from the state, and the force that does not come from springs:
// f0 = m (g - c v) + external. One loop per array group: GCC does not vectorize the mixed loop.
template <class T>
struct LoadArgs {
    const double *xs, *vs, *ext;
    const T* mass;
    T *x, *y, *z, *vx, *vy, *vz, *wx, *wy, *wz, *fx, *fy, *fz;
    T g[3], c;
};

template <class T>
CLOTH_SIMD_CLONES void loadState(const LoadArgs<T>& args, int begin, int end) {
    const double *__restrict xs = args.xs, *__restrict vs = args.vs, *__restrict ext = args.ext;
    const T* __restrict m = args.mass;
    T *__restrict x = args.x, *__restrict y = args.y, *__restrict z = args.z;
    T *__restrict vx = args.vx, *__restrict vy = args.vy, *__restrict vz = args.vz;
    T *__restrict wx = args.wx, *__restrict wy = args.wy, *__restrict wz = args.wz;
    T *__restrict fx = args.fx, *__restrict fy = args.fy, *__restrict fz = args.fz;
    const T gx = args.g[0], gy = args.g[1], gz = args.g[2], c = args.c;
CLOTH_IVDEP
    for (int i = begin; i < end; ++i) x[i] = T(xs[3 * i]), y[i] = T(xs[3 * i + 1]), z[i] = T(xs[3 * i + 2]);
CLOTH_IVDEP
    for (int i = begin; i < end; ++i) vx[i] = T(vs[3 * i]), vy[i] = T(vs[3 * i + 1]), vz[i] = T(vs[3 * i + 2]);
    std::copy(vx + begin, vx + end, wx + begin);
    std::copy(vy + begin, vy + end, wy + begin);
    std::copy(vz + begin, vz + end, wz + begin);
CLOTH_IVDEP
    for (int i = begin; i < end; ++i) {
        const T mi = m[i];
        fx[i] = mi * (gx - c * vx[i]);
        fy[i] = mi * (gy - c * vy[i]);
        fz[i] = mi * (gz - c * vz[i]);
    }
    if (ext)
    CLOTH_IVDEP
    for (int i = begin; i < end; ++i)
            fx[i] += T(ext[3 * i]), fy[i] += T(ext[3 * i + 1]), fz[i] += T(ext[3 * i + 2]);
}

// dv back in the state's layout (writeResult then puts the pins' prescribed change).
template <class T>
CLOTH_SIMD_CLONES void storeDv(const T* __restrict dx, const T* __restrict dy, const T* __restrict dz,
                               double* __restrict out, int begin, int end) {
CLOTH_IVDEP
    for (int i = begin; i < end; ++i) {
        out[3 * i] = double(dx[i]);
        out[3 * i + 1] = double(dy[i]);
        out[3 * i + 2] = double(dz[i]);
    }
}

}  // namespace

template <class T>
template <class Fn>
void StencilKangCho<T>::forBlocks(int n, const Fn& fn) {
    constexpr int kBlock = 8;  // thread chunks start on multiples of 8 (see the header)
    pool_.run((n + kBlock - 1) / kBlock,
              [&](int begin, int end) { fn(begin * kBlock, std::min(n, end * kBlock)); });
}

template <class T>
void StencilKangCho<T>::prepare(const Model& model) {
    modelId_ = model.id();
    n_ = model.particleCount();
    pad_ = offsets_.empty() ? 0 : offsets_.back();
    const std::size_t size = std::size_t(n_) + 2 * std::size_t(pad_);
    auto zero = [size](Field& f) { f.storage.assign(size, T(0)); };
    families_.assign(offsets_.size(), Family{});
    for (Family& f : families_)
        for (Field* field : {&f.k, &f.rest, &f.ux, &f.uy, &f.uz, &f.a, &f.b, &f.fm}) zero(*field);
    for (const Spring& s : model.springs()) {
        const int lo = int(std::min(s.i, s.j)), d = int(std::max(s.i, s.j)) - lo;
        const auto f = std::lower_bound(offsets_.begin(), offsets_.end(), d) - offsets_.begin();
        families_[f].k.at(pad_)[lo] = T(s.k);
        families_[f].rest.at(pad_)[lo] = T(s.rest);
    }
    zero(mass_);
    for (int i = 0; i < n_; ++i) mass_.at(pad_)[i] = T(model.masses()[i]);
    zero(pinned_);
    pinnedList_.clear();
    for (int a = 0; a < 3; ++a)
        for (Field* field : {&x_[a], &v_[a], &w_[a], &f0_[a], &pin_[a], &rhs_[a], &dvA_[a], &dvB_[a]}) zero(*field);
    for (Field& w : winv_) zero(w);
    for (Field& d : damp_) zero(d);
    dampingLoaded_ = false;
}

// Copies the state into the padded arrays and computes the force that does not come from springs:
// m (g - c v) + external.
template <class T>
void StencilKangCho<T>::loadFields(const Environment& env, const State& state, const StepInput& input) {
    const int n = n_, pad = pad_;
    const T c = T(env.drag);
    const T g[3] = {T(env.gravity.x()), T(env.gravity.y()), T(env.gravity.z())};
    const double* xs = state.x.data();
    const double* vs = state.v.data();
    const double* ext = input.externalForce ? input.externalForce->data() : nullptr;
    LoadArgs<T> la{xs, vs, ext, mass_.at(pad), x_[0].at(pad), x_[1].at(pad), x_[2].at(pad), v_[0].at(pad),
                   v_[1].at(pad), v_[2].at(pad), w_[0].at(pad), w_[1].at(pad), w_[2].at(pad), f0_[0].at(pad),
                   f0_[1].at(pad), f0_[2].at(pad), {g[0], g[1], g[2]}, c};
    forBlocks(n, [&](int begin, int end) { loadState(la, begin, end); });
}

// Clears the last step's pins and sets this step's: their prescribed dv, and w = v + dv.
template <class T>
void StencilKangCho<T>::setPins(const State& state, const StepInput& input) {
    const int n = n_, pad = pad_;
    for (const int i : pinnedList_) {  // clear the last step's pins only
        pinned_.at(pad)[i] = T(0);
        for (Field& f : pin_) f.at(pad)[i] = T(0);
    }
    pinnedList_.clear();
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        const int i = int(p.particle);
        pinned_.at(pad)[i] = T(1);
        pinnedList_.push_back(i);
        const Vec3 dv = pinVelocityChange(p, state.x.col(i), state.v.col(i), input.h);
        for (int a = 0; a < 3; ++a) {
            pin_[a].at(pad)[i] = T(dv[a]);
            w_[a].at(pad)[i] = v_[a].at(pad)[i] + pin_[a].at(pad)[i];
        }
    }
}

// Loads h C_i of an implicit external force (zero when there is none).
template <class T>
void StencilKangCho<T>::loadDamping(const StepInput& input, T h) {
    const int n = n_, pad = pad_;
    if (input.damping || dampingLoaded_) {
        static constexpr int kRow[6] = {0, 0, 0, 1, 1, 2}, kCol[6] = {0, 1, 2, 1, 2, 2};
        for (int e = 0; e < 6; ++e) {
            T* out = damp_[e].at(pad);
            for (int i = 0; i < n; ++i)
                out[i] = input.damping ? h * T((*input.damping)[i](kRow[e], kCol[e])) : T(0);
        }
        dampingLoaded_ = input.damping != nullptr;
    }
}

// Computes u, a, b and the force magnitude of every spring, one contiguous loop per family.
template <class T>
void StencilKangCho<T>::computeSprings(bool compressionRule) {
    const int n = n_, pad = pad_, nf = int(offsets_.size());
    forBlocks(n, [&](int begin, int end) {
        for (int f = 0; f < nf; ++f)
            springKernel<T>(x_[0].at(pad), x_[1].at(pad), x_[2].at(pad), families_[f].k.at(pad),
                            families_[f].rest.at(pad), compressionRule, viewOf<T>(families_[f], pad, offsets_[f]),
                            begin, end);
    });
}

// Writes dv back in the state's layout; pinned particles take their prescribed change (their dv is
// 0 in dvA_).
template <class T>
void StencilKangCho<T>::writeResult(Points& dv) {
    const int n = n_, pad = pad_;
    dv.resize(3, n);
    double* out = dv.data();
    const T *dx = dvA_[0].at(pad), *dy = dvA_[1].at(pad), *dz = dvA_[2].at(pad);
    forBlocks(n, [&](int begin, int end) { storeDv<T>(dx, dy, dz, out, begin, end); });
    for (const int i : pinnedList_)
        for (int a = 0; a < 3; ++a) out[3 * i + a] = double(pin_[a].at(pad)[i]);
}

template <class T>
void StencilKangCho<T>::solve(const StepProblem& problem, int iterations, Points& dv, double* forcesMs) {
    const auto& [model, env, state, input, compressionRule] = problem;
    const auto t0 = std::chrono::steady_clock::now();
    if (modelId_ != model.id()) prepare(model);
    const int n = n_, pad = pad_, nf = int(offsets_.size());
    const T h = T(input.h), c = T(env.drag);
    loadFields(env, state, input);
    setPins(state, input);
    loadDamping(input, h);

    // The springs, then per particle: b_i, W_ii^-1 and dv(0).
    SpringSide<T> sides[2 * kMaxFamilies];
    for (int f = 0; f < nf; ++f) {
        const FamilyView<T> F = viewOf<T>(families_[f], pad, offsets_[f]);
        const int d = F.d;
        sides[2 * f] = {F.ux, F.uy, F.uz, F.a, F.b, F.fm, d, T(1)};
        sides[2 * f + 1] = {F.ux - d, F.uy - d, F.uz - d, F.a - d, F.b - d, F.fm - d, -d, T(-1)};
    }
    ParticleArgs<T> pa;
    pa.sides = sides, pa.sideCount = 2 * nf;
    pa.vx = v_[0].at(pad), pa.vy = v_[1].at(pad), pa.vz = v_[2].at(pad);
    pa.f0x = f0_[0].at(pad), pa.f0y = f0_[1].at(pad), pa.f0z = f0_[2].at(pad);
    pa.wx = w_[0].at(pad), pa.wy = w_[1].at(pad), pa.wz = w_[2].at(pad);
    pa.pinned = pinned_.at(pad), pa.mass = mass_.at(pad);
    pa.rx = rhs_[0].at(pad), pa.ry = rhs_[1].at(pad), pa.rz = rhs_[2].at(pad);
    pa.w0 = winv_[0].at(pad), pa.w1 = winv_[1].at(pad), pa.w2 = winv_[2].at(pad);
    pa.w3 = winv_[3].at(pad), pa.w4 = winv_[4].at(pad), pa.w5 = winv_[5].at(pad);
    pa.dx = dvA_[0].at(pad), pa.dy = dvA_[1].at(pad), pa.dz = dvA_[2].at(pad);
    for (int e = 0; e < 6; ++e) pa.damp[e] = damp_[e].at(pad);
    pa.h = h, pa.c = c;
    computeSprings(compressionRule);
    forBlocks(n, [&](int begin, int end) { particleKernel(pa, begin, end); });
    if (forcesMs) *forcesMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // Jacobi sweeps from dv(0).
    SweepArgs<T> sa;
    sa.sides = sides, sa.sideCount = 2 * nf;
    sa.rx = pa.rx, sa.ry = pa.ry, sa.rz = pa.rz;
    sa.w0 = pa.w0, sa.w1 = pa.w1, sa.w2 = pa.w2, sa.w3 = pa.w3, sa.w4 = pa.w4, sa.w5 = pa.w5;
    sa.pinned = pa.pinned;
    sa.h2 = h * h;
    for (int k = 0; k < iterations; ++k) {
        sa.inx = dvA_[0].at(pad), sa.iny = dvA_[1].at(pad), sa.inz = dvA_[2].at(pad);
        sa.outx = dvB_[0].at(pad), sa.outy = dvB_[1].at(pad), sa.outz = dvB_[2].at(pad);
        forBlocks(n, [&](int begin, int end) { sweepKernel(sa, begin, end); });
        for (int a = 0; a < 3; ++a) std::swap(dvA_[a], dvB_[a]);
    }

    writeResult(dv);
}

template class StencilKangCho<float>;
template class StencilKangCho<double>;

}  // namespace cloth
