// Three-component GiNaC vectors in carrier axes: just enough algebra for the kinematics.
#pragma once

#include "model/model.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::symbolic {

using model::Vec3;

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator*(const GiNaC::ex& s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline GiNaC::ex dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline Vec3 diff(const Vec3& a, const GiNaC::symbol& s) {
    return {derivative(a[0], s), derivative(a[1], s), derivative(a[2], s)};
}
inline Vec3 zero_vector() { return {0, 0, 0}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
// A · v and Aᵀ · v for a 3×3 matrix.
inline Vec3 times(const GiNaC::matrix& A, const Vec3& v) {
    Vec3 out{0, 0, 0};
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 3; ++j) out[i] += A(i, j) * v[j];
    return out;
}
inline Vec3 transpose_times(const GiNaC::matrix& A, const Vec3& v) {
    Vec3 out{0, 0, 0};
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 3; ++j) out[i] += A(j, i) * v[j];
    return out;
}

}  // namespace eomc::symbolic
