#pragma once
// orient3d with its sign settled exactly, for the crossing checker (cloth/crossings.h).
//
// orient3d(a, b, c, d) = det[a - d; b - d; c - d] (the rows are the differences): positive when
// d lies below the plane through a, b, c, which appear counterclockwise seen from above; zero when
// the four points are coplanar; six times the signed volume of the tetrahedron.
//
// The filter evaluates the determinant in long double (inputs are doubles, exactly representable
// in long double; every operation rounds with unit roundoff u = epsilon / 2 = 2^-64 on x86-64).
// Shewchuk's analysis of this expression ("Adaptive precision floating-point arithmetic and fast
// robust geometric predicates", 1997: orient3d's bound A) holds in any binary floating-point
// format with unit roundoff u: |computed - exact| <= (7 + 56 u) u * permanent, where permanent is
// the same expression with every product replaced by its absolute value, itself computed in that
// arithmetic. The filter trusts the sign when |computed| > 8 u * permanent (8 u >= (7 + 56 u) u).
// long double's exponent range (to 2^-16382) is far beyond any product of three differences of
// doubles, so no underflow or overflow voids the bound.
//
// Otherwise the determinant is recomputed exactly: the 4 x 4 determinant of the rows [a 1],
// [b 1], [c 1], [d 1] (equal to the one above: subtract the last row from the others) is a sum of
// 24 signed products of three coordinates. Each product of three doubles is split exactly into
// four long doubles with fmal (x y = p + e exactly with p = fl(x y), e = fmal(x, y, -p); then p z
// and e z likewise), and the 96 terms are summed exactly into a nonoverlapping expansion
// (Shewchuk's Grow-Expansion with Knuth's TwoSum). The sign of such an expansion is the sign of
// its largest component. Every step is exact for all finite doubles: a product of three doubles
// and the errors of its roundings lie between 2^-3300 and 2^3100, inside long double's range.

#include "cloth/types.h"

namespace cloth::crossings {

// The sign (-1, 0, +1) of orient3d(a, b, c, d), exact: the filter, then the exact sum near zero.
int orient3dSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The same sign from the exact sum alone (no filter).
int orient3dSignExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace cloth::crossings
