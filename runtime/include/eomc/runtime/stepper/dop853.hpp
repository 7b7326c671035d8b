#pragma once

// Dormand-Prince 8(5,3) ("DOP853"): the 12-stage eighth-order method of Prince and Dormand with
// FSAL, fifth- and third-order embedded error estimates combined as in Hairer's code, and the
// seventh-order continuous extension (dense output) that needs three extra stages per step.
// References:
//   P.J. Prince, J.R. Dormand, "High order embedded Runge-Kutta formulae", J. Comput. Appl. Math.
//     7 (1981) 67-75 (the 8(7) tableau);
//   [HNW] Hairer-Norsett-Wanner I, 2nd ed., Sect. II.5 (DOP853, error estimator (5.5)-(5.6)) and
//     Sect. II.6 (its dense output); the coefficients are those of Hairer's Fortran code dop853.f
//     (version of 2004), read from the faithful transcription in SciPy,
//     scipy/integrate/_ivp/dop853_coefficients.py (30 significant digits, so long double gets
//     long double accuracy and float128 30 digits, see coefficients.hpp).
// Optionally with compensated (Kahan) summation of the update (ControlledStepper::set_compensated).

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <utility>

#include "eomc/runtime/checker.hpp"
#include "eomc/runtime/stepper/coefficients.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/extent.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/concepts.hpp"
#include "eomc/runtime/control/controlled.hpp"
#include "eomc/runtime/control/step_adjuster.hpp"

namespace eomc::runtime {

namespace detail {

// Stage numbering from 0: stages 0..11 are the method, 12 is f(t+h, y_new) (FSAL, also used by
// the dense output), 13..15 are the extra dense-output stages. a[i][j] = 0 for j >= i.
inline constexpr Coefficient dop853_c[16] = {
    EOMC_COEFFICIENT(0.0),
    EOMC_COEFFICIENT(0.526001519587677318785587544488e-01),
    EOMC_COEFFICIENT(0.789002279381515978178381316732e-01),
    EOMC_COEFFICIENT(0.118350341907227396726757197510),
    EOMC_COEFFICIENT(0.281649658092772603273242802490),
    EOMC_COEFFICIENT(0.333333333333333333333333333333),
    EOMC_COEFFICIENT(0.25),
    EOMC_COEFFICIENT(0.307692307692307692307692307692),
    EOMC_COEFFICIENT(0.651282051282051282051282051282),
    EOMC_COEFFICIENT(0.6),
    EOMC_COEFFICIENT(0.857142857142857142857142857142),
    EOMC_COEFFICIENT(1.0),
    EOMC_COEFFICIENT(1.0),
    EOMC_COEFFICIENT(0.1),
    EOMC_COEFFICIENT(0.2),
    EOMC_COEFFICIENT(0.777777777777777777777777777778)};

inline constexpr Coefficient dop853_a[16][16] = {
    {},
    {EOMC_COEFFICIENT(5.26001519587677318785587544488e-2)},
    {EOMC_COEFFICIENT(1.97250569845378994544595329183e-2), EOMC_COEFFICIENT(5.91751709536136983633785987549e-2)},
    {EOMC_COEFFICIENT(2.95875854768068491816892993775e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(8.87627564304205475450678981324e-2)},
    {EOMC_COEFFICIENT(2.41365134159266685502369798665e-1), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-8.84549479328286085344864962717e-1),
     EOMC_COEFFICIENT(9.24834003261792003115737966543e-1)},
    {EOMC_COEFFICIENT(3.7037037037037037037037037037e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(1.70828608729473871279604482173e-1),
     EOMC_COEFFICIENT(1.25467687566822425016691814123e-1)},
    {EOMC_COEFFICIENT(3.7109375e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(1.70252211019544039314978060272e-1), EOMC_COEFFICIENT(6.02165389804559606850219397283e-2),
     EOMC_COEFFICIENT(-1.7578125e-2)},
    {EOMC_COEFFICIENT(3.70920001185047927108779319836e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(1.70383925712239993810214054705e-1),
     EOMC_COEFFICIENT(1.07262030446373284651809199168e-1), EOMC_COEFFICIENT(-1.53194377486244017527936158236e-2),
     EOMC_COEFFICIENT(8.27378916381402288758473766002e-3)},
    {EOMC_COEFFICIENT(6.24110958716075717114429577812e-1), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-3.36089262944694129406857109825),
     EOMC_COEFFICIENT(-8.68219346841726006818189891453e-1), EOMC_COEFFICIENT(2.75920996994467083049415600797e1),
     EOMC_COEFFICIENT(2.01540675504778934086186788979e1), EOMC_COEFFICIENT(-4.34898841810699588477366255144e1)},
    {EOMC_COEFFICIENT(4.77662536438264365890433908527e-1), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-2.48811461997166764192642586468),
     EOMC_COEFFICIENT(-5.90290826836842996371446475743e-1), EOMC_COEFFICIENT(2.12300514481811942347288949897e1),
     EOMC_COEFFICIENT(1.52792336328824235832596922938e1), EOMC_COEFFICIENT(-3.32882109689848629194453265587e1),
     EOMC_COEFFICIENT(-2.03312017085086261358222928593e-2)},
    {EOMC_COEFFICIENT(-9.3714243008598732571704021658e-1), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(5.18637242884406370830023853209),
     EOMC_COEFFICIENT(1.09143734899672957818500254654), EOMC_COEFFICIENT(-8.14978701074692612513997267357),
     EOMC_COEFFICIENT(-1.85200656599969598641566180701e1), EOMC_COEFFICIENT(2.27394870993505042818970056734e1),
     EOMC_COEFFICIENT(2.49360555267965238987089396762), EOMC_COEFFICIENT(-3.0467644718982195003823669022)},
    {EOMC_COEFFICIENT(2.27331014751653820792359768449), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-1.05344954667372501984066689879e1),
     EOMC_COEFFICIENT(-2.00087205822486249909675718444), EOMC_COEFFICIENT(-1.79589318631187989172765950534e1),
     EOMC_COEFFICIENT(2.79488845294199600508499808837e1), EOMC_COEFFICIENT(-2.85899827713502369474065508674),
     EOMC_COEFFICIENT(-8.87285693353062954433549289258), EOMC_COEFFICIENT(1.23605671757943030647266201528e1),
     EOMC_COEFFICIENT(6.43392746015763530355970484046e-1)},
    // Row 12: the eighth-order weights b (y_new = x + h sum b_j k_j; b_1..b_4 = 0).
    {EOMC_COEFFICIENT(5.42937341165687622380535766363e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(4.45031289275240888144113950566),
     EOMC_COEFFICIENT(1.89151789931450038304281599044), EOMC_COEFFICIENT(-5.8012039600105847814672114227), EOMC_COEFFICIENT(3.1116436695781989440891606237e-1),
     EOMC_COEFFICIENT(-1.52160949662516078556178806805e-1), EOMC_COEFFICIENT(2.01365400804030348374776537501e-1),
     EOMC_COEFFICIENT(4.47106157277725905176885569043e-2)},
    {EOMC_COEFFICIENT(5.61675022830479523392909219681e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(2.53500210216624811088794765333e-1),
     EOMC_COEFFICIENT(-2.46239037470802489917441475441e-1), EOMC_COEFFICIENT(-1.24191423263816360469010140626e-1),
     EOMC_COEFFICIENT(1.5329179827876569731206322685e-1), EOMC_COEFFICIENT(8.20105229563468988491666602057e-3),
     EOMC_COEFFICIENT(7.56789766054569976138603589584e-3), EOMC_COEFFICIENT(-8.298e-3)},
    {EOMC_COEFFICIENT(3.18346481635021405060768473261e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(2.83009096723667755288322961402e-2),
     EOMC_COEFFICIENT(5.35419883074385676223797384372e-2), EOMC_COEFFICIENT(-5.49237485713909884646569340306e-2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0),
     EOMC_COEFFICIENT(-1.08347328697249322858509316994e-4), EOMC_COEFFICIENT(3.82571090835658412954920192323e-4),
     EOMC_COEFFICIENT(-3.40465008687404560802977114492e-4), EOMC_COEFFICIENT(1.41312443674632500278074618366e-1)},
    {EOMC_COEFFICIENT(-4.28896301583791923408573538692e-1), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-4.69762141536116384314449447206),
     EOMC_COEFFICIENT(7.68342119606259904184240953878), EOMC_COEFFICIENT(4.06898981839711007970213554331), EOMC_COEFFICIENT(3.56727187455281109270669543021e-1),
     EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-1.39902416515901462129418009734e-3), EOMC_COEFFICIENT(2.9475147891527723389556272149),
     EOMC_COEFFICIENT(-9.15095847217987001081870187138)}};

// Fifth-order error estimator: err5 = h sum e5_j k_j  (dop853.f: ER1, ER6..ER12).
inline constexpr Coefficient dop853_e5[12] = {
    EOMC_COEFFICIENT(0.1312004499419488073250102996e-1), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-0.1225156446376204440720569753e1),
    EOMC_COEFFICIENT(-0.4957589496572501915214079952),   EOMC_COEFFICIENT(0.1664377182454986536961530415e1),
    EOMC_COEFFICIENT(-0.3503288487499736816886487290),   EOMC_COEFFICIENT(0.3341791187130174790297318841),
    EOMC_COEFFICIENT(0.8192320648511571246570742613e-1), EOMC_COEFFICIENT(-0.2235530786388629525884427845e-1)};

// Third-order embedded weights bhh (on stages 0, 8 and 11; dop853.f: BHH1..BHH3); the third-order
// error estimate is err3 = h sum (b_j - bhh_j) k_j.
inline constexpr Coefficient dop853_bhh[3] = {EOMC_COEFFICIENT(0.244094488188976377952755905512), EOMC_COEFFICIENT(0.733846688281611857341361741547),
                                              EOMC_COEFFICIENT(0.220588235294117647058823529412e-1)};

// Dense output: the coefficients d_{4..7,j} of dop853.f (D41..D716), on all 16 stages.
inline constexpr Coefficient dop853_d[4][16] = {
    {EOMC_COEFFICIENT(-0.84289382761090128651353491142e1), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.56671495351937776962531783590),
     EOMC_COEFFICIENT(-0.30689499459498916912797304727e1), EOMC_COEFFICIENT(0.23846676565120698287728149680e1), EOMC_COEFFICIENT(0.21170345824450282767155149946e1),
     EOMC_COEFFICIENT(-0.87139158377797299206789907490), EOMC_COEFFICIENT(0.22404374302607882758541771650e1), EOMC_COEFFICIENT(0.63157877876946881815570249290),
     EOMC_COEFFICIENT(-0.88990336451333310820698117400e-1), EOMC_COEFFICIENT(0.18148505520854727256656404962e2),
     EOMC_COEFFICIENT(-0.91946323924783554000451984436e1), EOMC_COEFFICIENT(-0.44360363875948939664310572000e1)},
    {EOMC_COEFFICIENT(0.10427508642579134603413151009e2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.24228349177525818288430175319e3),
     EOMC_COEFFICIENT(0.16520045171727028198505394887e3), EOMC_COEFFICIENT(-0.37454675472269020279518312152e3),
     EOMC_COEFFICIENT(-0.22113666853125306036270938578e2), EOMC_COEFFICIENT(0.77334326684722638389603898808e1),
     EOMC_COEFFICIENT(-0.30674084731089398182061213626e2), EOMC_COEFFICIENT(-0.93321305264302278729567221706e1),
     EOMC_COEFFICIENT(0.15697238121770843886131091075e2), EOMC_COEFFICIENT(-0.31139403219565177677282850411e2),
     EOMC_COEFFICIENT(-0.93529243588444783865713862664e1), EOMC_COEFFICIENT(0.35816841486394083752465898540e2)},
    {EOMC_COEFFICIENT(0.19985053242002433820987653617e2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-0.38703730874935176555105901742e3),
     EOMC_COEFFICIENT(-0.18917813819516756882830838328e3), EOMC_COEFFICIENT(0.52780815920542364900561016686e3),
     EOMC_COEFFICIENT(-0.11573902539959630126141871134e2), EOMC_COEFFICIENT(0.68812326946963000169666922661e1),
     EOMC_COEFFICIENT(-0.10006050966910838403183860980e1), EOMC_COEFFICIENT(0.77771377980534432092869265740),
     EOMC_COEFFICIENT(-0.27782057523535084065932004339e1), EOMC_COEFFICIENT(-0.60196695231264120758267380846e2),
     EOMC_COEFFICIENT(0.84320405506677161018159903784e2), EOMC_COEFFICIENT(0.11992291136182789328035130030e2)},
    {EOMC_COEFFICIENT(-0.25693933462703749003312586129e2), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(0.0), EOMC_COEFFICIENT(-0.15418974869023643374053993627e3),
     EOMC_COEFFICIENT(-0.23152937917604549567536039109e3), EOMC_COEFFICIENT(0.35763911791061412378285349910e3),
     EOMC_COEFFICIENT(0.93405324183624310003907691704e2), EOMC_COEFFICIENT(-0.37458323136451633156875139351e2),
     EOMC_COEFFICIENT(0.10409964950896230045147246184e3), EOMC_COEFFICIENT(0.29840293426660503123344363579e2),
     EOMC_COEFFICIENT(-0.43533456590011143754432175058e2), EOMC_COEFFICIENT(0.96324553959188282948394950600e2),
     EOMC_COEFFICIENT(-0.39177261675615439165231486172e2), EOMC_COEFFICIENT(-0.14972683625798562581422125276e3)}};

}  // namespace detail

// The DOP853 coefficients rounded once to S (read from their digits for scalars wider than long
// double, see coefficients.hpp).
template <class S>
struct Dop853Tableau {
  static constexpr int stages = 12, dense_stages = 16;

  static constexpr std::array<S, 16> c = [] {
    std::array<S, 16> r{};
    for (int i = 0; i < 16; ++i) r[i] = detail::coefficient<S>(detail::dop853_c[i]);
    return r;
  }();
  static constexpr std::array<std::array<S, 16>, 16> a = [] {
    std::array<std::array<S, 16>, 16> r{};
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) r[i][j] = detail::coefficient<S>(detail::dop853_a[i][j]);
    return r;
  }();
  // b_j = a[12][j].
  static constexpr std::array<S, 12> e5 = [] {
    std::array<S, 12> r{};
    for (int j = 0; j < 12; ++j) r[j] = detail::coefficient<S>(detail::dop853_e5[j]);
    return r;
  }();
  // The third-order weights on stages 0, 8, 11: err3 = h (sum_j b_j k_j - bhh . (k_0, k_8, k_11)).
  static constexpr std::array<S, 3> bhh = [] {
    std::array<S, 3> r{};
    for (int j = 0; j < 3; ++j) r[j] = detail::coefficient<S>(detail::dop853_bhh[j]);
    return r;
  }();
  static constexpr std::array<std::array<S, 16>, 4> d = [] {
    std::array<std::array<S, 16>, 4> r{};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 16; ++j) r[i][j] = detail::coefficient<S>(detail::dop853_d[i][j]);
    return r;
  }();

  // Whether a[i][j] is non-zero, decided on the long double table so that it is a constant
  // expression whatever S is.
  static constexpr bool a_nonzero(int i, int j) { return detail::dop853_a[i][j].value != 0.0L; }
  static constexpr bool e5_nonzero(int j) { return detail::dop853_e5[j].value != 0.0L; }
};

// The DOP853 pair as an error stepper (stepper/concepts.hpp): the stages, the combined error
// estimate, the dense output; ControlledStepper (control/controlled.hpp) adds the control.
template <class S>
class Dop853ErrorStepper {
 public:
  using value_type = S;
  // error_order is the exponent the controller uses, err ~ h^(error_order+1) = h^8 as in dop853.f
  // (the combined estimate below behaves like h^8 for small h, see attempt).
  static constexpr int order = 8, error_order = 7;
  static constexpr const char* name = "Dop853";

  // dense_output = false skips the three extra stages per accepted step (then calc_state throws).
  explicit Dop853ErrorStepper(bool dense_output = true) : dense_enabled_(dense_output) {}

  template <class Sys>
  void evaluate_first(Sys& sys, S t, const State<S>& x) {
    resize(x.size());
    sys(t, x, k_[0]);
    ++rhs_evals_;
  }
  const State<S>& first_derivative() const { return k_[0]; }

  // Stages 1..11, the eighth-order solution and the error norm of dop853.f ([HNW] II.5,
  // (5.5)-(5.6)): with the RMS norms n5 = ||err5 / sc||, n3 = ||err3 / sc|| (sc_i = atol + rtol
  // max(|x_i|, |y_new_i|)),
  //   err = n5^2 / sqrt(n5^2 + 0.01 n3^2),
  // which is ~ n5^2 / (0.1 n3) = O(h^6 * h^6 / h^4) = O(h^8) for small h and ~ n5 for large h.
  template <class Sys, class Checker>
  S attempt(Sys& sys, const State<S>& x, S t, S h, const Checker& checker, const S* comp, S* comp_new) {
    using std::isfinite;
    using std::sqrt;
    S n5 = S(0), n3 = S(0);
    detail::with_extent(x.size(), [&](auto n) {
      stages(sys, x, t, h, n);
      last_row(x, h, n, comp, comp_new, std::make_index_sequence<T::stages>{});
      error_norms(x, checker, n, n5, n3);
    });
    // Written as n5 / sqrt(1 + 0.01 (n3/n5)^2) so that large norms do not overflow; NaN or Inf in
    // either estimate makes the error non-finite (rejection with the largest reduction).
    if (!isfinite(n5) || !isfinite(n3)) return std::numeric_limits<S>::infinity();
    if (n5 == S(0)) return S(0);
    const S q = n3 / n5;
    return n5 / sqrt(S(1) + S(0.01) * q * q);
  }

  template <class Sys>
  void advance(Sys& sys, const State<S>& x, S t, S h, const S* comp, S* comp_new) {
    detail::with_extent(x.size(), [&](auto n) {
      stages(sys, x, t, h, n);
      last_row(x, h, n, comp, comp_new, std::make_index_sequence<T::stages>{});
    });
  }

  // Commits the step (t, x) -> (t+h, ynew_): FSAL stage f(t+h, ynew_), dense-output coefficients
  // (three more stages when enabled), x.
  template <class Sys>
  void accept(Sys& sys, State<S>& x, S t, S h) {
    const std::size_t n = x.size();
    const S t_end = t + h;
    const State<S>& yn = ynew_;
    sys(t_end, yn, k_[12]);
    ++rhs_evals_;
    if (dense_enabled_) {
      const State<S>& y = y_;
      for (int s = 13; s < 16; ++s) {
        combine(y_, x, h, s, s);
        sys(t + T::c[s] * h, y, k_[s]);
      }
      rhs_evals_ += 3;
      for (std::size_t i = 0; i < n; ++i) {
        const S dx = ynew_[i] - x[i];
        r_[0][i] = x[i];
        r_[1][i] = dx;
        r_[2][i] = h * k_[0][i] - dx;
        r_[3][i] = dx - h * k_[12][i] - r_[2][i];
        for (int m = 0; m < 4; ++m) {
          S acc = 0;
          for (int j = 0; j < 16; ++j) acc += T::d[m][j] * k_[j][i];
          r_[4 + m][i] = h * acc;
        }
      }
      t_old_ = t;
      h_old_ = h;
      dense_valid_ = true;
    }
    for (std::size_t i = 0; i < n; ++i) x[i] = ynew_[i];  // copy: the caller's buffer stays put
    t_new_ = t_end;
    if (!dense_enabled_) t_old_ = t;
    k_[0].swap(k_[12]);
  }

  // Dense output on the last accepted step [t_old, t_new] (dop853.f, CONTD8):
  //   u(s) = r0 + s(r1 + s'(r2 + s(r3 + s'(r4 + s(r5 + s'(r6 + s r7)))))),  s = (tau - t_old)/h, s' = 1-s,
  // a seventh-order interpolant (local error O(h^8)), exact at both step ends and C1 across steps.
  void calc_state(S tau, State<S>& out) const {
    if (!dense_valid_) throw std::logic_error("Dop853::calc_state: no accepted step with dense output yet");
    const S s = (tau - t_old_) / h_old_, s1 = S(1) - s;
    const std::size_t n = r_[0].size();
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      out[i] = r_[0][i] +
               s * (r_[1][i] +
                    s1 * (r_[2][i] +
                          s * (r_[3][i] + s1 * (r_[4][i] + s * (r_[5][i] + s1 * (r_[6][i] + s * r_[7][i]))))));
  }

  S previous_time() const { return t_old_; }
  S current_time() const { return t_new_; }
  bool has_dense_output() const { return dense_valid_; }
  void invalidate_dense_output() { dense_valid_ = false; }
  bool dense_output_enabled() const { return dense_enabled_; }
  std::size_t rhs_evals() const { return rhs_evals_; }

  std::size_t locate_non_finite() const {
    for (int s = 1; s < T::stages; ++s) {
      const std::size_t i = first_non_finite(k_[s]);
      if (i != IntegrationError::no_component) return i;
    }
    std::size_t i = first_non_finite(ynew_);
    if (i == IntegrationError::no_component) i = first_non_finite(err5_);
    if (i == IntegrationError::no_component) i = first_non_finite(err3_);
    return i;
  }

 private:
  using T = Dop853Tableau<S>;

  // y = x + h * sum_{j < upto} a[row][j] k_j (dense-output stages; not on the hot path).
  void combine(State<S>& y, const State<S>& x, S h, int row, int upto) const {
    for (std::size_t i = 0; i < x.size(); ++i) {
      S acc = 0;
      for (int j = 0; j < upto; ++j) acc += T::a[row][j] * k_[j][i];
      y[i] = x[i] + h * acc;
    }
  }

  // The stage rows below are unrolled at compile time, zero coefficients dropped (about half of
  // the a_ij), and run over n components, n a compile-time constant for small systems (see
  // detail::with_extent). For a 4-component system this makes a step about a third cheaper than
  // loops over j and i with run-time bounds.

  // Stages 1..11 from (t, x) with step h.
  template <class Sys, class N>
  void stages(Sys& sys, const State<S>& x, S t, S h, N n) {
    stage_rows(sys, x, t, h, n, std::make_integer_sequence<int, T::stages - 1>{});
    rhs_evals_ += T::stages - 1;
  }

  template <class Sys, class N, int... R>
  void stage_rows(Sys& sys, const State<S>& x, S t, S h, N n, std::integer_sequence<int, R...>) {
    (stage<R + 1>(sys, x, t, h, n), ...);
  }

  template <int Row, class Sys, class N>
  void stage(Sys& sys, const State<S>& x, S t, S h, N n) {
    stage_state<Row>(x.data(), h, n, std::make_index_sequence<Row>{});
    const State<S>& y = y_;
    sys(Row == T::stages - 1 ? t + h : t + T::c[Row] * h, y, k_[Row]);
  }

  // y_ = x + h sum_{j < Row} a[Row][j] k_j.
  template <int Row, class N, std::size_t... J>
  void stage_state(const S* x, S h, N n, std::index_sequence<J...>) {
    const S* const k[] = {k_[J].data()...};
    S* y = y_.data();
    for (std::size_t i = 0; i < n; ++i) {
      S acc = S(0);
      ([&] {
        if constexpr (T::a_nonzero(Row, J)) acc += T::a[Row][J] * k[J][i];
      }(), ...);
      y[i] = x[i] + h * acc;
    }
  }

  // The eighth-order solution ynew_ = x + h sum_j b_j k_j and the two error estimates
  // err5 = h sum_j e5_j k_j and err3 = h (sum_j b_j k_j - bhh . k) (dop853.f's form).
  template <class N, std::size_t... J>
  void last_row(const State<S>& x, S h, N n, const S* comp, S* comp_new, std::index_sequence<J...>) {
    constexpr int B = T::stages;
    const S* const k[] = {k_[J].data()...};
    for (std::size_t i = 0; i < n; ++i) {
      S b = S(0), e5 = S(0);
      ([&] {
        if constexpr (T::a_nonzero(B, J)) b += T::a[B][J] * k[J][i];
      }(), ...);
      ([&] {
        if constexpr (T::e5_nonzero(J)) e5 += T::e5[J] * k[J][i];
      }(), ...);
      if (comp) {
        const S inc = h * b - comp[i];
        ynew_[i] = x[i] + inc;
        comp_new[i] = (ynew_[i] - x[i]) - inc;
      } else {
        ynew_[i] = x[i] + h * b;
      }
      err5_[i] = h * e5;
      err3_[i] = h * (b - (T::bhh[0] * k[0][i] + T::bhh[1] * k[8][i] + T::bhh[2] * k[11][i]));
    }
  }

  // The RMS norms of err5_ and err3_ scaled as the checker does, in one pass.
  template <class Checker, class N>
  void error_norms(const State<S>& x, const Checker& checker, N n, S& n5, S& n3) const {
    using std::sqrt;
    S sum5 = S(0), sum3 = S(0);
    for (std::size_t i = 0; i < n; ++i) {
      const S sc = checker.scale(x[i], ynew_[i]);
      const S r5 = Checker::ratio(err5_[i], sc), r3 = Checker::ratio(err3_[i], sc);
      sum5 += r5 * r5;
      sum3 += r3 * r3;
    }
    const S count = S(static_cast<std::size_t>(n) > 0 ? static_cast<std::size_t>(n) : 1);
    n5 = sqrt(sum5 / count);
    n3 = sqrt(sum3 / count);
  }

  void resize(std::size_t n) {
    if (k_[0].size() == n) return;
    for (State<S>& v : k_) v.assign(n, S(0));
    for (State<S>& v : r_) v.assign(n, S(0));
    for (State<S>* v : {&y_, &ynew_, &err5_, &err3_}) v->assign(n, S(0));
    dense_valid_ = false;
  }

  bool dense_enabled_;
  std::array<State<S>, 16> k_;
  State<S> y_, ynew_, err5_, err3_;
  std::array<State<S>, 8> r_;  // dense-output coefficients of the last accepted step
  S t_old_ = S(0), t_new_ = S(0), h_old_ = S(0);
  bool dense_valid_ = false;
  std::size_t rhs_evals_ = 0;
};

// DOP853 under its controller (below). Same interface as Dopri5, so a driver templated on the
// stepper can use either.
template <class S>
class Dop853 : public ControlledStepper<Dop853ErrorStepper<S>> {
 public:
  using Settings = typename StepAdjuster<S>::Settings;

  // The controller of dop853.f: the step may shrink to 0.333 and grow to 6 times per attempt, no
  // PI term (BETA = 0; were it set, dop853.f's exponent is 1/8 - 0.2 BETA). Two changes, measured
  // on Kepler orbits over 10 periods at rtol = atol = 1e-6 .. 1e-13 (bench/dop853_controller.cpp):
  //  * Gustafsson's predictive controller is on (see StepAdjuster). With dop853.f's plain
  //    controller an orbit of e = 0.6 rejects 29% of the attempts at 1e-6 .. 1e-10 (nearly every
  //    step on the way into pericentre is tried twice), with it 5-10%; at equal final error that
  //    is up to 20% fewer system calls (e = 0.3, 0.6, 0.9).
  //  * safety 0.85 instead of 0.9: with prediction, about as much work at equal error, half the
  //    remaining rejections, and an error that falls with every tighter tolerance (with 0.9 it
  //    stalls between 1e-6 and 1e-7 at e = 0.6).
  static Settings default_settings() {
    Settings s;
    s.safety = S(0.85);
    s.fac_min = S(0.333);
    s.fac_max = S(6);
    s.beta = S(0);
    s.beta_weight = S(0.2);
    s.predictive = true;
    return s;
  }

  // dense_output = false skips the three extra stages per accepted step (then calc_state throws);
  // the stepper then costs 12 system calls per accepted and 11 per rejected step.
  explicit Dop853(Settings settings = default_settings(), bool dense_output = true)
      : ControlledStepper<Dop853ErrorStepper<S>>(Dop853ErrorStepper<S>(dense_output), settings) {}

  bool dense_output_enabled() const { return this->error_stepper().dense_output_enabled(); }
};

static_assert(ErrorStepper<Dop853ErrorStepper<double>> && AdaptiveStepper<Dop853<double>> &&
              DenseOutputStepper<Dop853<double>>);
static_assert(AdaptiveStepper<Dop853<long double>> && DenseOutputStepper<Dop853<long double>>);

}  // namespace eomc::runtime
