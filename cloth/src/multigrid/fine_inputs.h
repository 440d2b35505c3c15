#pragma once
// What the finest level's assembly reads of a step: the state, the step's constants, the pinned
// particles and the terms of b that no spring gives.

#include "../simd.h"

namespace cloth {

// b_i's terms without springs: h (m_i (g - c v_i) + external_i).
template <class T>
struct RowForces {
    const double* mass;
    const double* vs;
    const double* ext;  // null: no external force
    T g[3];
    T c, h;
    CLOTH_INLINE void add(int i, T* r) const {
        const T m = T(mass[i]);
        for (int a = 0; a < 3; ++a)
            r[a] += h * (m * (g[a] - c * T(vs[3 * i + a])) + (ext ? T(ext[3 * i + a]) : T(0)));
    }
};

template <class T>
struct FineInputs {
    const double* xs;  // positions, 3n particle-major
    const double* vs;  // velocities
    T h, h2;
    bool compressionRule;
    const unsigned char* pinned;
    const T* base;   // 6n: the spring-free part of W_ii (mass, drag, damping)
    const T* pinDv;  // 3n: the pinned particles' prescribed change
    RowForces<T> rows;
};

}  // namespace cloth
