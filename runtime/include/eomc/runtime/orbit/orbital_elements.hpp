#pragma once

// Orbital elements <-> Cartesian state for the two-body problem r'' = -mu r/|r|^3.
//
//   Cartesian      (x, y, z, vx, vy, vz)
//   classical      (a, e, i, raan, argp, mean_anomaly)   radians; a < 0 on hyperbolas
//   equinoctial    (p, f, g, h, k, L)                    modified equinoctial, retrograde factor +1
//   Delaunay       (l, g, h, L, G, H)                    ellipses only
//
// References: [Vallado] Fundamentals of Astrodynamics and Applications, 4th ed., Algorithms 9
// (RV2COE) and 10 (COE2RV) and their special cases; [WIO] M. J. H. Walker, B. Ireland, J. Owens,
// A set of modified equinoctial orbit elements, Celest. Mech. 36 (1985) 409-419, with the
// equinoctial frame f = (1 - k^2 + h^2, 2hk, -2k)/s^2,
// g = (2hk, 1 + k^2 - h^2, 2h)/s^2, s^2 = 1 + h^2 + k^2; [Brouwer-Clemence] Methods of Celestial
// Mechanics (1961): Delaunay L = sqrt(mu a), G = L sqrt(1 - e^2), H = G cos i.
//
// Angles: raan, argp in [0, 2 pi); i in [0, pi]; mean_anomaly in [0, 2 pi) on ellipses and
// unbounded on hyperbolas (negative before periapsis); L (true longitude) in [0, 2 pi).
//
// Singular cases of the classical elements (state -> elements), with the conventional zeros:
//   equatorial (|h_x|, |h_y| <= 16 eps |h|, i = 0 or pi): raan = 0, the node line is the x axis;
//   circular (e <= 16 eps): argp = 0, the periapsis direction is the node line, so the
//     "mean anomaly" is the mean argument of latitude (the true longitude if also equatorial).
// Below those thresholds the angles are round-off anyway; above them the general formulas are
// used (the orientation they give is still well defined, only ill-conditioned). Exactly parabolic
// orbits (e = 1, 1/a = 0) have no classical a: KeplerError::invalid_input; use the equinoctial p.
// The modified equinoctial elements are regular at e = 0 and i = 0; they are singular at i = pi.
//
// Scalars: as for kepler.hpp (double, long double, or a class type with ADL math functions).

#include <array>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>

#include "eomc/runtime/orbit/kepler.hpp"

namespace eomc::runtime {

template <class S>
using CartesianState = std::array<S, 6>;  // x, y, z, vx, vy, vz

template <class S>
struct ClassicalElements {
  S a, e, i, raan, argp, mean_anomaly;
};
template <class S>
struct EquinoctialElements {
  S p, f, g, h, k, L;
};
template <class S>
struct DelaunayElements {
  S l, g, h, L, G, H;
};

// State names used by CSV output and summaries.
inline constexpr std::array<const char*, 6> cartesian_names{"x", "y", "z", "vx", "vy", "vz"};
inline constexpr std::array<const char*, 6> classical_names{"a", "e", "i", "raan", "argp", "mean_anomaly"};
inline constexpr std::array<const char*, 6> equinoctial_names{"p", "f", "g", "h", "k", "L"};
inline constexpr std::array<const char*, 6> delaunay_names{"l", "g", "h", "L", "G", "H"};

namespace elements_detail {

template <class S>
using Vec3 = std::array<S, 3>;

template <class S>
Vec3<S> cross(const Vec3<S>& a, const Vec3<S>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <class S>
S dot(const Vec3<S>& a, const Vec3<S>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class S>
S norm(const Vec3<S>& a) {
  using std::sqrt;
  return sqrt(elements_detail::dot(a, a));
}

// Angle from direction u to direction w, counterclockwise about the unit normal n:
// atan2((u x w) . n, u . w); u and w need not be unit vectors.
template <class S>
S angle_about(const Vec3<S>& u, const Vec3<S>& w, const Vec3<S>& n) {
  using std::atan2;
  return atan2(elements_detail::dot(elements_detail::cross(u, w), n), elements_detail::dot(u, w));
}

// (-pi, pi] -> [0, 2 pi).
template <class S>
S wrap_positive(S x) {
  const S two_pi = S(2) * kepler_detail::pi<S>();
  if (x < S(0)) {
    x += two_pi;
    if (x >= two_pi) x = S(0);
  }
  return x;
}

template <class S>
void check_mu(const char* where, S mu) {
  if (!(mu > S(0)) || !kepler_detail::finite(mu)) throw KeplerError::invalid(where, "mu not positive and finite", mu);
}

// Position and velocity in the perifocal frame (x toward periapsis) from a, e, M.
// Ellipse: x = a (cos E - e), y = a eta sin E, r = a (1 - e cos E), v = sqrt(mu a)/r (-sin E, eta cos E),
// eta = sqrt((1-e)(1+e)); hyperbola (a < 0): x = a (cosh H - e), y = -a eta sinh H,
// r = a (1 - e cosh H), v = sqrt(-mu a)/r (-sinh H, eta cosh H), eta = sqrt((e-1)(e+1)).
// cos E - e and 1 - e cos E are formed as (1 - e) - (1 - cos E) and (1 - e) + e (1 - cos E), so the
// periapsis distance a (1 - e) of a near-parabolic orbit keeps its accuracy.
template <class S>
void perifocal(S a, S e, S M, S mu, S& x, S& y, S& vx, S& vy) {
  using std::cos;
  using std::cosh;
  using std::sin;
  using std::sinh;
  using std::sqrt;
  namespace kd = kepler_detail;
  if (e < S(1)) {
    const S E = runtime::eccentric_from_mean(M, e);
    const S sE = sin(E), cE = cos(E), hE = kd::one_minus_cos(E);
    const S eta = sqrt((S(1) - e) * (S(1) + e));
    const S r = a * ((S(1) - e) + e * hE);
    x = a * ((S(1) - e) - hE);
    y = a * eta * sE;
    const S vf = sqrt(mu * a) / r;
    vx = -vf * sE;
    vy = vf * eta * cE;
  } else {
    const S H = runtime::hyperbolic_from_mean(M, e);
    const S sH = sinh(H), cH = cosh(H), hH = kd::cosh_minus_one(H);
    const S eta = sqrt((e - S(1)) * (e + S(1)));
    const S r = -a * ((e - S(1)) + e * hH);
    x = a * (hH - (e - S(1)));
    y = -a * eta * sH;
    const S vf = sqrt(-mu * a) / r;
    vx = -vf * sH;
    vy = vf * eta * cH;
  }
}

}  // namespace elements_detail

// ---------------------------------------------------------------------------------------------
// Classical elements.

// [Vallado Alg. 10] Perifocal position and velocity rotated by R3(-raan) R1(-i) R3(-argp).
template <class S>
CartesianState<S> cartesian_from_classical(const ClassicalElements<S>& el, S mu) {
  using std::cos;
  using std::sin;
  namespace kd = kepler_detail;
  namespace ed = elements_detail;
  constexpr const char* where = "cartesian_from_classical";
  ed::check_mu(where, mu);
  for (const S* v : {&el.a, &el.e, &el.i, &el.raan, &el.argp, &el.mean_anomaly})
    kd::check_finite(where, "element not finite", *v);
  if (!(el.e >= S(0))) throw KeplerError::invalid(where, "negative eccentricity: e", el.e);
  if (el.e == S(1)) throw KeplerError::invalid(where, "parabolic orbit has no semi-major axis: e", el.e);
  if (el.e < S(1) && !(el.a > S(0))) throw KeplerError::invalid(where, "ellipse needs a > 0: a", el.a);
  if (el.e > S(1) && !(el.a < S(0))) throw KeplerError::invalid(where, "hyperbola needs a < 0: a", el.a);

  S xp, yp, vxp, vyp;
  ed::perifocal(el.a, el.e, el.mean_anomaly, mu, xp, yp, vxp, vyp);
  const S cO = cos(el.raan), sO = sin(el.raan), cw = cos(el.argp), sw = sin(el.argp);
  const S ci = cos(el.i), si = sin(el.i);
  // Columns of the rotation: P (toward periapsis) and Q (90 degrees ahead in the orbit plane).
  const S P[3] = {cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si};
  const S Q[3] = {-cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si};
  CartesianState<S> x;
  for (std::size_t j = 0; j < 3; ++j) {
    x[j] = xp * P[j] + yp * Q[j];
    x[j + 3] = vxp * P[j] + vyp * Q[j];
  }
  return x;
}

// [Vallado Alg. 9] with atan2 forms throughout: i = atan2(|h_xy|, h_z), raan = atan2(h_x, -h_y),
// argp = angle from the node n = z x h to e about h, nu = angle from e to r about h; a from the
// energy, e = |v x h/mu - r/|r||, M from nu through E (ellipses) or from e sinh H = r.v/sqrt(-mu a)
// (hyperbolas). Special cases: see the header comment.
template <class S>
ClassicalElements<S> classical_from_cartesian(const CartesianState<S>& x, S mu) {
  using std::atan2;
  using std::sqrt;
  namespace kd = kepler_detail;
  namespace ed = elements_detail;
  constexpr const char* where = "classical_from_cartesian";
  ed::check_mu(where, mu);
  for (const S& c : x) kd::check_finite(where, "state component not finite", c);
  const ed::Vec3<S> r{x[0], x[1], x[2]}, v{x[3], x[4], x[5]};
  const S rn = ed::norm(r);
  const ed::Vec3<S> h = ed::cross(r, v);
  const S hn = ed::norm(h);
  if (!(hn > S(0))) throw KeplerError::invalid(where, "rectilinear or degenerate state, |r x v|", hn);
  const ed::Vec3<S> hu{h[0] / hn, h[1] / hn, h[2] / hn};
  const ed::Vec3<S> vxh = ed::cross(v, h);
  const ed::Vec3<S> ev{vxh[0] / mu - r[0] / rn, vxh[1] / mu - r[1] / rn, vxh[2] / mu - r[2] / rn};
  const S e = ed::norm(ev);
  const S alpha = S(2) / rn - ed::dot(v, v) / mu;  // 1/a from the energy
  if (alpha == S(0)) throw KeplerError::invalid(where, "parabolic orbit (1/a = 0) has no semi-major axis: e", e);
  if ((alpha > S(0)) != (e < S(1)))
    throw KeplerError::invalid(where, "energy and eccentricity disagree on the conic (parabolic within round-off): e", e);

  const S tol = S(16) * kd::eps<S>();
  const S nxy = sqrt(h[0] * h[0] + h[1] * h[1]);
  const bool equatorial = nxy <= tol * hn;
  const bool circular = e <= tol;
  // Node line: z x h, or the x axis on equatorial orbits. Periapsis direction: e, or the node line.
  const ed::Vec3<S> node = equatorial ? ed::Vec3<S>{S(1), S(0), S(0)} : ed::Vec3<S>{-h[1], h[0], S(0)};
  const ed::Vec3<S> peri = circular ? node : ev;

  ClassicalElements<S> el;
  el.a = S(1) / alpha;
  el.e = e;
  el.i = atan2(nxy, h[2]);
  el.raan = equatorial ? S(0) : ed::wrap_positive(atan2(h[0], -h[1]));
  el.argp = circular ? S(0) : ed::wrap_positive(ed::angle_about(node, peri, hu));
  if (e < S(1)) {
    // Through nu measured from the computed periapsis direction, so that errors of that direction
    // (eps/e on near-circular orbits) cancel between argp and M.
    const S nu = ed::angle_about(peri, r, hu);
    el.mean_anomaly = ed::wrap_positive(runtime::mean_from_eccentric(runtime::eccentric_from_true(nu, e), e));
  } else {
    // e sinh H = (r . v)/sqrt(-mu a) straight from the state: through nu, H would inherit the
    // amplification d H/d nu = (e cosh H - 1)/sqrt(e^2 - 1) of the asymptotic branches.
    using std::asinh;
    el.mean_anomaly = runtime::mean_from_hyperbolic(asinh(ed::dot(r, v) / (e * sqrt(-mu * el.a))), e);
  }
  return el;
}

// ---------------------------------------------------------------------------------------------
// Modified equinoctial elements [WIO]: p = a (1 - e^2), f = e cos(argp + raan),
// g = e sin(argp + raan), h = tan(i/2) cos raan, k = tan(i/2) sin raan, L = raan + argp + nu.

namespace elements_detail {
template <class S>
void equinoctial_frame(S h, S k, Vec3<S>& fu, Vec3<S>& gu) {
  const S s2 = S(1) + h * h + k * k;
  fu = {(S(1) - k * k + h * h) / s2, S(2) * h * k / s2, S(-2) * k / s2};
  gu = {S(2) * h * k / s2, (S(1) + k * k - h * h) / s2, S(2) * h / s2};
}
}  // namespace elements_detail

// r = p/w (cos L f + sin L g), v = sqrt(mu/p) (-(g + sin L) f + (f + cos L) g), w = 1 + f cos L + g sin L.
template <class S>
CartesianState<S> cartesian_from_equinoctial(const EquinoctialElements<S>& el, S mu) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  namespace kd = kepler_detail;
  namespace ed = elements_detail;
  constexpr const char* where = "cartesian_from_equinoctial";
  ed::check_mu(where, mu);
  for (const S* v : {&el.p, &el.f, &el.g, &el.h, &el.k, &el.L}) kd::check_finite(where, "element not finite", *v);
  if (!(el.p > S(0))) throw KeplerError::invalid(where, "semi-latus rectum not positive: p", el.p);
  ed::Vec3<S> fu, gu;
  ed::equinoctial_frame(el.h, el.k, fu, gu);
  const S cL = cos(el.L), sL = sin(el.L);
  const S w = S(1) + el.f * cL + el.g * sL;
  if (!(w > S(0))) throw KeplerError::invalid(where, "true longitude beyond the asymptote: L", el.L);
  const S r = el.p / w;
  const S vs = sqrt(mu / el.p);
  const S rf = r * cL, rg = r * sL, vf = -vs * (el.g + sL), vg = vs * (el.f + cL);
  CartesianState<S> x;
  for (std::size_t j = 0; j < 3; ++j) {
    x[j] = rf * fu[j] + rg * gu[j];
    x[j + 3] = vf * fu[j] + vg * gu[j];
  }
  return x;
}

// Directly from the state, without passing through the singular angles: p = |h|^2/mu,
// h = -h_y/(|h| + h_z), k = h_x/(|h| + h_z) (tan(i/2) times the node direction), f and g the
// components of the eccentricity vector on the equinoctial frame, L = atan2(r.g, r.f).
template <class S>
EquinoctialElements<S> equinoctial_from_cartesian(const CartesianState<S>& x, S mu) {
  using std::atan2;
  namespace kd = kepler_detail;
  namespace ed = elements_detail;
  constexpr const char* where = "equinoctial_from_cartesian";
  ed::check_mu(where, mu);
  for (const S& c : x) kd::check_finite(where, "state component not finite", c);
  const ed::Vec3<S> r{x[0], x[1], x[2]}, v{x[3], x[4], x[5]};
  const S rn = ed::norm(r);
  const ed::Vec3<S> hv = ed::cross(r, v);
  const S hn = ed::norm(hv);
  if (!(hn > S(0))) throw KeplerError::invalid(where, "rectilinear or degenerate state, |r x v|", hn);
  const S den = hn + hv[2];
  if (!(den > S(0))) throw KeplerError::invalid(where, "retrograde equatorial orbit (i = pi) is singular: h_z/|h|", hv[2] / hn);
  EquinoctialElements<S> el;
  el.p = hn * hn / mu;
  el.h = -hv[1] / den;
  el.k = hv[0] / den;
  ed::Vec3<S> fu, gu;
  ed::equinoctial_frame(el.h, el.k, fu, gu);
  const ed::Vec3<S> vxh = ed::cross(v, hv);
  const ed::Vec3<S> ev{vxh[0] / mu - r[0] / rn, vxh[1] / mu - r[1] / rn, vxh[2] / mu - r[2] / rn};
  el.f = ed::dot(ev, fu);
  el.g = ed::dot(ev, gu);
  el.L = ed::wrap_positive(atan2(ed::dot(r, gu), ed::dot(r, fu)));
  return el;
}

template <class S>
EquinoctialElements<S> equinoctial_from_classical(const ClassicalElements<S>& el) {
  using std::cos;
  using std::sin;
  using std::tan;
  namespace ed = elements_detail;
  if (!(el.i < kepler_detail::pi<S>()))
    throw KeplerError::invalid("equinoctial_from_classical", "retrograde equatorial orbit (i = pi) is singular: i", el.i);
  const S lp = el.raan + el.argp;  // longitude of periapsis
  const S t = tan(el.i / S(2));
  EquinoctialElements<S> q;
  q.p = el.a * (S(1) - el.e) * (S(1) + el.e);
  q.f = el.e * cos(lp);
  q.g = el.e * sin(lp);
  q.h = t * cos(el.raan);
  q.k = t * sin(el.raan);
  S rev;
  q.L = ed::wrap_positive(kepler_detail::reduce_angle(lp + runtime::true_from_mean(el.mean_anomaly, el.e), rev));
  return q;
}

// e = |(f, g)|, i = 2 atan |(h, k)|, raan = atan2(k, h), argp = atan2(g, f) - raan; the
// conventional zeros when e = 0 (argp = 0) or h = k = 0 (raan = 0) exactly.
template <class S>
ClassicalElements<S> classical_from_equinoctial(const EquinoctialElements<S>& q) {
  using std::atan;
  using std::atan2;
  using std::sqrt;
  namespace ed = elements_detail;
  const S e = sqrt(q.f * q.f + q.g * q.g);
  const S t = sqrt(q.h * q.h + q.k * q.k);
  if (e == S(1)) throw KeplerError::invalid("classical_from_equinoctial", "parabolic orbit has no semi-major axis: e", e);
  ClassicalElements<S> el;
  el.e = e;
  el.a = q.p / ((S(1) - e) * (S(1) + e));
  el.i = S(2) * atan(t);
  el.raan = t == S(0) ? S(0) : ed::wrap_positive(atan2(q.k, q.h));
  const S lp = e == S(0) ? el.raan : atan2(q.g, q.f);
  S rev;
  el.argp = ed::wrap_positive(kepler_detail::reduce_angle(lp - el.raan, rev));
  const S nu = kepler_detail::reduce_angle(q.L - lp, rev);
  el.mean_anomaly = e < S(1) ? ed::wrap_positive(runtime::mean_from_true(nu, e)) : runtime::mean_from_true(nu, e);
  return el;
}

// ---------------------------------------------------------------------------------------------
// Delaunay variables (ellipses): l = M, g = argp, h = raan, L = sqrt(mu a), G = L sqrt(1 - e^2),
// H = G cos i (Brouwer and Clemence, Methods of Celestial Mechanics, 1961).

template <class S>
DelaunayElements<S> delaunay_from_classical(const ClassicalElements<S>& el, S mu) {
  using std::cos;
  using std::sqrt;
  elements_detail::check_mu("delaunay_from_classical", mu);
  if (!(el.e >= S(0) && el.e < S(1) && el.a > S(0)))
    throw KeplerError::invalid("delaunay_from_classical", "Delaunay variables need an ellipse: e", el.e);
  DelaunayElements<S> d;
  d.l = el.mean_anomaly;
  d.g = el.argp;
  d.h = el.raan;
  d.L = sqrt(mu * el.a);
  d.G = d.L * sqrt((S(1) - el.e) * (S(1) + el.e));
  d.H = d.G * cos(el.i);
  return d;
}

// a = L^2/mu, e = sqrt((L - G)(L + G))/L, i = atan2(sqrt((G - H)(G + H)), H): the factored forms
// keep e and i accurate when G -> L (near-circular) and |H| -> G (near-equatorial).
template <class S>
ClassicalElements<S> classical_from_delaunay(const DelaunayElements<S>& d, S mu) {
  using std::abs;
  using std::atan2;
  using std::sqrt;
  constexpr const char* where = "classical_from_delaunay";
  elements_detail::check_mu(where, mu);
  if (!(d.L > S(0) && d.G > S(0) && d.G <= d.L && abs(d.H) <= d.G))
    throw KeplerError::invalid(where, "need 0 < G <= L and |H| <= G: G", d.G);
  ClassicalElements<S> el;
  el.a = d.L * d.L / mu;
  el.e = sqrt((d.L - d.G) * (d.L + d.G)) / d.L;
  el.i = atan2(sqrt((d.G - d.H) * (d.G + d.H)), d.H);
  el.raan = d.h;
  el.argp = d.g;
  el.mean_anomaly = d.l;
  return el;
}

}  // namespace eomc::runtime
