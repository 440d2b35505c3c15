#include "kangcho/stencil.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "kernels.h"
#include "simd.h"

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

template <class T>
struct FamilyView {
    const T *ux, *uy, *uz, *a, *b, *fm;
    int d;
};

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
CLOTH_SIMD_CLONES void springKernel(const T* __restrict x, const T* __restrict y, const T* __restrict z, int d,
                                    const T* __restrict k, const T* __restrict rest, bool compressionRule,
                                    T* __restrict ux, T* __restrict uy, T* __restrict uz, T* __restrict a,
                                    T* __restrict b, T* __restrict fm, int begin, int end) {
    for (int p = begin; p < end; ++p) {
        const SpringTerms<T> t =
            springTerms(x[p + d] - x[p], y[p + d] - y[p], z[p + d] - z[p], k[p], rest[p], compressionRule);
        ux[p] = t.ux, uy[p] = t.uy, uz[p] = t.uz, a[p] = t.a, b[p] = t.b, fm[p] = t.fm;
    }
}

// The particle passes walk their range in tiles; per tile, each family and each end of its
// springs is one short loop that adds into accumulators the size of a tile (they stay in L1), so
// a loop body holds a few arrays, not all of them. A spring is seen from its lower end (slot t,
// other end t + d, u pointing away: sign +1) and from its upper end (slot t - d, other end t - d,
// sign -1). Tiles are kTile rows (simd.h).

struct TileRange {
    int begin, n;
};

// s += sum over the springs of each particle in the tile of J_ij q_j (the off-diagonal product
// of eq. 11, without the h^2 factor).
template <class T>
CLOTH_INLINE inline void addOffDiagonal(const FamilyView<T>* families, int count, const T* qx0, const T* qy0,
                                        const T* qz0, TileRange tile, T* __restrict sx, T* __restrict sy,
                                        T* __restrict sz) {
    for (int f = 0; f < count; ++f)
        for (const int side : {1, -1}) {
            const FamilyView<T>& F = families[f];
            const int slot = tile.begin + (side > 0 ? 0 : -F.d), other = tile.begin + side * F.d;
            const T *__restrict ux = F.ux + slot, *__restrict uy = F.uy + slot, *__restrict uz = F.uz + slot;
            const T *__restrict a = F.a + slot, *__restrict b = F.b + slot;
            const T *__restrict qx = qx0 + other, *__restrict qy = qy0 + other, *__restrict qz = qz0 + other;
CLOTH_IVDEP
            for (int t = 0; t < tile.n; ++t)
                addJacobianTimes(a[t], b[t], ux[t], uy[t], uz[t], qx[t], qy[t], qz[t], sx[t], sy[t], sz[t]);
        }
}

template <class T>
struct ParticleArgs {
    const FamilyView<T>* fam;
    int families;
    const T *vx, *vy, *vz, *wx, *wy, *wz, *f0x, *f0y, *f0z, *pinned, *mass;
    const T* damp[6];  // h C_i of the external force (xx xy xz yy yz zz), zero when explicit
    T *rx, *ry, *rz, *w0, *w1, *w2, *w3, *w4, *w5, *dx, *dy, *dz;
    T h, c;
};

// Per particle: f, W_ii (eq. 12), b_i (eq. 7, pinned columns moved to the right), W_ii^-1 and
// dv(0) = W_ii^-1 b_i (eq. 11). The b_i term sum_j J_ij (w_j - v_i) is computed as
// sum_j J_ij w_j - (A I + B) v_i, the first part by the sweep's own product; w = v + the
// prescribed dv of pinned particles (v elsewhere) carries the pinned columns. Pinned particles
// get dv = 0 here: their prescribed dv is already in their neighbours' b_i, and solve() writes
// it into the result.
template <class T>
CLOTH_SIMD_CLONES void particleKernel(const ParticleArgs<T>& args, int begin, int end) {
    const T h = args.h, h2 = h * h, c = args.c;
    alignas(64) T fx[kTile], fy[kTile], fz[kTile], jx[kTile], jy[kTile], jz[kTile];
    alignas(64) T A[kTile], Bxx[kTile], Bxy[kTile], Bxz[kTile], Byy[kTile], Byz[kTile], Bzz[kTile];
    for (int first = begin; first < end; first += kTile) {
        const TileRange tile{first, std::min(kTile, end - first)};
        const int n = tile.n;
        for (int t = 0; t < n; ++t) {
            fx[t] = args.f0x[first + t], fy[t] = args.f0y[first + t], fz[t] = args.f0z[first + t];
            jx[t] = jy[t] = jz[t] = A[t] = Bxx[t] = Bxy[t] = Bxz[t] = Byy[t] = Byz[t] = Bzz[t] = T(0);
        }
        for (int f = 0; f < args.families; ++f)
            for (const int side : {1, -1}) {
                const FamilyView<T>& F = args.fam[f];
                const int slot = first + (side > 0 ? 0 : -F.d);
                const T sign = T(side);
                const T *__restrict ux = F.ux + slot, *__restrict uy = F.uy + slot, *__restrict uz = F.uz + slot;
                const T *__restrict fa = F.a + slot, *__restrict fb = F.b + slot, *__restrict fm = F.fm + slot;
CLOTH_IVDEP
                for (int t = 0; t < n; ++t) {
                    const T x = ux[t], y = uy[t], z = uz[t], b = fb[t], fs = sign * fm[t];
                    fx[t] += fs * x, fy[t] += fs * y, fz[t] += fs * z;
                    A[t] += fa[t];
                    Bxx[t] += b * x * x, Bxy[t] += b * x * y, Bxz[t] += b * x * z;
                    Byy[t] += b * y * y, Byz[t] += b * y * z, Bzz[t] += b * z * z;
                }
            }
        addOffDiagonal(args.fam, args.families, args.wx, args.wy, args.wz, tile, jx, jy, jz);
        const T *__restrict vx = args.vx + first, *__restrict vy = args.vy + first, *__restrict vz = args.vz + first;
        const T *__restrict pinned = args.pinned + first, *__restrict mass = args.mass + first;
        T *__restrict rx = args.rx + first, *__restrict ry = args.ry + first, *__restrict rz = args.rz + first;
        T *__restrict w0 = args.w0 + first, *__restrict w1 = args.w1 + first, *__restrict w2 = args.w2 + first;
        T *__restrict w3 = args.w3 + first, *__restrict w4 = args.w4 + first, *__restrict w5 = args.w5 + first;
        T *__restrict dx = args.dx + first, *__restrict dy = args.dy + first, *__restrict dz = args.dz + first;
        const T *__restrict c0 = args.damp[0] + first, *__restrict c1 = args.damp[1] + first;
        const T *__restrict c2 = args.damp[2] + first, *__restrict c3 = args.damp[3] + first;
        const T *__restrict c4 = args.damp[4] + first, *__restrict c5 = args.damp[5] + first;
CLOTH_IVDEP
        for (int t = 0; t < n; ++t) {
            // sum_j J_ij (w_j - v_i) = sum_j J_ij w_j - (A I + B) v_i
            const T Ka = A[t], kxx = Ka + Bxx[t], kxy = Bxy[t], kxz = Bxz[t];
            const T kyy = Ka + Byy[t], kyz = Byz[t], kzz = Ka + Bzz[t];
            const T ex = jx[t] - (kxx * vx[t] + kxy * vy[t] + kxz * vz[t]);
            const T ey = jy[t] - (kxy * vx[t] + kyy * vy[t] + kyz * vz[t]);
            const T ez = jz[t] - (kxz * vx[t] + kyz * vy[t] + kzz * vz[t]);
            const T r0 = h * fx[t] + h2 * ex, r1 = h * fy[t] + h2 * ey, r2 = h * fz[t] + h2 * ez;
            // W = m (1 + h c) I + h C + h^2 (A I + B), as 6 numbers, and its inverse.
            const T diag = mass[t] * (T(1) + h * c);
            const T W[6] = {diag + c0[t] + h2 * kxx, c1[t] + h2 * kxy, c2[t] + h2 * kxz,
                            diag + c3[t] + h2 * kyy, c4[t] + h2 * kyz, diag + c5[t] + h2 * kzz};
            T inv[6];
            symmetricInverse(W, inv);
            const T i0 = inv[0], i1 = inv[1], i2 = inv[2], i3 = inv[3], i4 = inv[4], i5 = inv[5];
            rx[t] = r0, ry[t] = r1, rz[t] = r2;
            w0[t] = i0, w1[t] = i1, w2[t] = i2, w3[t] = i3, w4[t] = i4, w5[t] = i5;
            const bool free = pinned[t] == T(0);
            dx[t] = free ? i0 * r0 + i1 * r1 + i2 * r2 : T(0);
            dy[t] = free ? i1 * r0 + i3 * r1 + i4 * r2 : T(0);
            dz[t] = free ? i2 * r0 + i4 * r1 + i5 * r2 : T(0);
        }
    }
}

template <class T>
struct SweepArgs {
    const FamilyView<T>* fam;
    int families;
    const T *rx, *ry, *rz, *w0, *w1, *w2, *w3, *w4, *w5, *pinned, *inx, *iny, *inz;
    T *outx, *outy, *outz;
    T h2;
};

// One Jacobi sweep (eq. 11; from dv(0) it is eq. 14): dv_i = W_ii^-1 (b_i + h^2 sum_j J dv_j).
// Pinned particles hold dv = 0, so their columns (already in b_i) add nothing.
template <class T>
CLOTH_SIMD_CLONES void sweepKernel(const SweepArgs<T>& args, int begin, int end) {
    const T h2 = args.h2;
    alignas(64) T sx[kTile], sy[kTile], sz[kTile];
    for (int first = begin; first < end; first += kTile) {
        const TileRange tile{first, std::min(kTile, end - first)};
        for (int t = 0; t < tile.n; ++t) sx[t] = sy[t] = sz[t] = T(0);
        addOffDiagonal(args.fam, args.families, args.inx, args.iny, args.inz, tile, sx, sy, sz);
        const T *__restrict rx = args.rx + first, *__restrict ry = args.ry + first, *__restrict rz = args.rz + first;
        const T *__restrict w0 = args.w0 + first, *__restrict w1 = args.w1 + first, *__restrict w2 = args.w2 + first;
        const T *__restrict w3 = args.w3 + first, *__restrict w4 = args.w4 + first, *__restrict w5 = args.w5 + first;
        const T* __restrict pinned = args.pinned + first;
        T *__restrict outx = args.outx + first, *__restrict outy = args.outy + first, *__restrict outz = args.outz + first;
CLOTH_IVDEP
        for (int t = 0; t < tile.n; ++t) {
            const T y0 = rx[t] + h2 * sx[t], y1 = ry[t] + h2 * sy[t], y2 = rz[t] + h2 * sz[t];
            const bool free = pinned[t] == T(0);
            outx[t] = free ? w0[t] * y0 + w1[t] * y1 + w2[t] * y2 : T(0);
            outy[t] = free ? w1[t] * y0 + w3[t] * y1 + w4[t] * y2 : T(0);
            outz[t] = free ? w2[t] * y0 + w4[t] * y1 + w5[t] * y2 : T(0);
        }
    }
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

// dv back in the state's layout; pinned particles take their prescribed change.
template <class T, class Field>
CLOTH_SIMD_CLONES void storeDv(Field* dvf, Field* pinf, const T* __restrict pinned, int pad, double* __restrict out,
                               int begin, int end) {
    const T *__restrict dx = dvf[0].at(pad), *__restrict dy = dvf[1].at(pad), *__restrict dz = dvf[2].at(pad);
    const T *__restrict px = pinf[0].at(pad), *__restrict py = pinf[1].at(pad), *__restrict pz = pinf[2].at(pad);
CLOTH_IVDEP
    for (int i = begin; i < end; ++i) {
        const bool free = pinned[i] == T(0);
        out[3 * i] = double(free ? dx[i] : px[i]);
        out[3 * i + 1] = double(free ? dy[i] : py[i]);
        out[3 * i + 2] = double(free ? dz[i] : pz[i]);
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
        for (int f = 0; f < nf; ++f) {
            Family& F = families_[f];
            springKernel<T>(x_[0].at(pad), x_[1].at(pad), x_[2].at(pad), offsets_[f], F.k.at(pad), F.rest.at(pad),
                            compressionRule, F.ux.at(pad), F.uy.at(pad), F.uz.at(pad), F.a.at(pad), F.b.at(pad),
                            F.fm.at(pad), begin, end);
        }
    });
}

// Writes dv back in the state's layout; pinned particles take their prescribed change.
template <class T>
void StencilKangCho<T>::writeResult(Points& dv) {
    const int n = n_, pad = pad_;
    dv.resize(3, n);
    double* out = dv.data();
    forBlocks(n, [&](int begin, int end) { storeDv<T>(dvA_, pin_, pinned_.at(pad), pad, out, begin, end); });
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
    computeSprings(compressionRule);

    // Per particle: b_i, W_ii^-1 and dv(0).
    FamilyView<T> views[kMaxFamilies] = {};
    for (int f = 0; f < nf; ++f) {
        Family& F = families_[f];
        views[f] = {F.ux.at(pad), F.uy.at(pad), F.uz.at(pad), F.a.at(pad), F.b.at(pad), F.fm.at(pad), offsets_[f]};
    }
    ParticleArgs<T> pa;
    pa.fam = views, pa.families = nf;
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
    forBlocks(n, [&](int begin, int end) { particleKernel(pa, begin, end); });
    if (forcesMs) *forcesMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // Jacobi sweeps from dv(0).
    SweepArgs<T> sa;
    sa.fam = views, sa.families = nf;
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
