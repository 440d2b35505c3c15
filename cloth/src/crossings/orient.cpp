#include "crossings/orient.h"

#include <array>
#include <cmath>
#include <limits>

namespace cloth::crossings {

namespace {

using Long = long double;

// The exact path needs a long double with more digits than a double and an exponent range that
// holds a product of three doubles with the errors of its roundings (x87 extended, IEEE quad).
static_assert(std::numeric_limits<Long>::digits >= 64, "the crossing checker needs an extended long double");
static_assert(std::numeric_limits<Long>::min_exponent < -3400 && std::numeric_limits<Long>::max_exponent > 3200,
              "the crossing checker needs long double's extended exponent range");

constexpr Long kUnitRoundoff = std::numeric_limits<Long>::epsilon() / 2;
// Shewchuk's orient3d bound A is (7 + 56 u) u * permanent; 8 u covers it.
constexpr Long kFilterBound = 8 * kUnitRoundoff;

// det = adz (bdx cdy - bdy cdx) + bdz (cdx ady - cdy adx) + cdz (adx bdy - ady bdx), with
// the differences ad = a - d, bd = b - d, cd = c - d; zero when |det| is within the bound.
int filteredSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, bool& sure) {
    const Long adx = Long(a.x()) - d.x(), ady = Long(a.y()) - d.y(), adz = Long(a.z()) - d.z();
    const Long bdx = Long(b.x()) - d.x(), bdy = Long(b.y()) - d.y(), bdz = Long(b.z()) - d.z();
    const Long cdx = Long(c.x()) - d.x(), cdy = Long(c.y()) - d.y(), cdz = Long(c.z()) - d.z();
    const Long bdxcdy = bdx * cdy, bdycdx = bdy * cdx;
    const Long cdxady = cdx * ady, cdyadx = cdy * adx;
    const Long adxbdy = adx * bdy, adybdx = ady * bdx;
    const Long det = adz * (bdxcdy - bdycdx) + bdz * (cdxady - cdyadx) + cdz * (adxbdy - adybdx);
    const Long permanent = (std::fabs(bdxcdy) + std::fabs(bdycdx)) * std::fabs(adz) +
                           (std::fabs(cdxady) + std::fabs(cdyadx)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(adybdx)) * std::fabs(cdz);
    const Long bound = kFilterBound * permanent;
    sure = det > bound || -det > bound;
    return (det > 0) - (det < 0);
}

// s + e = x + y exactly, s = fl(x + y) (Knuth's TwoSum).
void twoSum(Long x, Long y, Long& s, Long& e) {
    s = x + y;
    const Long yVirtual = s - x;
    const Long xVirtual = s - yVirtual;
    e = (x - xVirtual) + (y - yVirtual);
}

// h = e + b exactly, e nonoverlapping in increasing magnitude (n terms), zeros dropped
// (Shewchuk's Grow-Expansion). Returns h's length, at most n + 1; h may be e.
int grow(Long* e, int n, Long b) {
    Long q = b;
    int k = 0;
    for (int i = 0; i < n; ++i) {
        Long sum, err;
        twoSum(q, e[i], sum, err);
        q = sum;
        if (err != 0) e[k++] = err;
    }
    if (q != 0 || k == 0) e[k++] = q;
    return k;
}

// sign x y z = four long doubles, exactly: x y = p + e (p = fl(x y), e = fmal(x, y, -p)),
// then p z and e z split the same way.
std::array<Long, 4> product3(Long sign, Long x, Long y, Long z) {
    const Long p = x * y, e = std::fmal(x, y, -p);
    const Long pz = p * z, ez = e * z;
    return {sign * pz, sign * std::fmal(p, z, -pz), sign * ez, sign * std::fmal(e, z, -ez)};
}

struct Permutation { int i, j, k; Long sign; };
constexpr std::array<Permutation, 6> kPermutations = {{
    {0, 1, 2, 1}, {1, 2, 0, 1}, {2, 0, 1, 1}, {0, 2, 1, -1}, {2, 1, 0, -1}, {1, 0, 2, -1}}};

}  // namespace

// det[[a 1], [b 1], [c 1], [d 1]] = sum over rows r of (-1)^(r + 3) det3(the other rows), each
// det3(u, v, w) = sum over permutations s of sign(s) u[s0] v[s1] w[s2]: 96 exact terms.
int orient3dSignExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const std::array<const Vec3*, 4> rows = {&a, &b, &c, &d};
    std::array<Long, 97> expansion{};
    int length = 0;
    for (int r = 0; r < 4; ++r) {
        std::array<const Vec3*, 3> m{};
        for (int i = 0, k = 0; i < 4; ++i)
            if (i != r) m[k++] = rows[i];
        const Long rowSign = (r % 2 == 0) ? -1 : 1;
        for (const Permutation& s : kPermutations)
            for (const Long term : product3(rowSign * s.sign, (*m[0])(s.i), (*m[1])(s.j), (*m[2])(s.k)))
                if (term != 0) length = grow(expansion.data(), length, term);
    }
    const Long top = length > 0 ? expansion[length - 1] : 0;
    return (top > 0) - (top < 0);
}

int orient3dSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    bool sure = false;
    const int sign = filteredSign(a, b, c, d, sure);
    return sure ? sign : orient3dSignExact(a, b, c, d);
}

}  // namespace cloth::crossings
