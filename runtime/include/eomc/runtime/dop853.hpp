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
//     long double accuracy).

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "eomc/runtime/checker.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/step_control.hpp"

namespace eomc::runtime {

namespace detail {

// Stage numbering from 0: stages 0..11 are the method, 12 is f(t+h, y_new) (FSAL, also used by
// the dense output), 13..15 are the extra dense-output stages. a[i][j] = 0 for j >= i.
inline constexpr long double dop853_c[16] = {
    0.0L,
    0.526001519587677318785587544488e-01L,
    0.789002279381515978178381316732e-01L,
    0.118350341907227396726757197510L,
    0.281649658092772603273242802490L,
    0.333333333333333333333333333333L,
    0.25L,
    0.307692307692307692307692307692L,
    0.651282051282051282051282051282L,
    0.6L,
    0.857142857142857142857142857142L,
    1.0L,
    1.0L,
    0.1L,
    0.2L,
    0.777777777777777777777777777778L};

inline constexpr long double dop853_a[16][16] = {
    {},
    {5.26001519587677318785587544488e-2L},
    {1.97250569845378994544595329183e-2L, 5.91751709536136983633785987549e-2L},
    {2.95875854768068491816892993775e-2L, 0.0L, 8.87627564304205475450678981324e-2L},
    {2.41365134159266685502369798665e-1L, 0.0L, -8.84549479328286085344864962717e-1L,
     9.24834003261792003115737966543e-1L},
    {3.7037037037037037037037037037e-2L, 0.0L, 0.0L, 1.70828608729473871279604482173e-1L,
     1.25467687566822425016691814123e-1L},
    {3.7109375e-2L, 0.0L, 0.0L, 1.70252211019544039314978060272e-1L, 6.02165389804559606850219397283e-2L,
     -1.7578125e-2L},
    {3.70920001185047927108779319836e-2L, 0.0L, 0.0L, 1.70383925712239993810214054705e-1L,
     1.07262030446373284651809199168e-1L, -1.53194377486244017527936158236e-2L,
     8.27378916381402288758473766002e-3L},
    {6.24110958716075717114429577812e-1L, 0.0L, 0.0L, -3.36089262944694129406857109825L,
     -8.68219346841726006818189891453e-1L, 2.75920996994467083049415600797e1L,
     2.01540675504778934086186788979e1L, -4.34898841810699588477366255144e1L},
    {4.77662536438264365890433908527e-1L, 0.0L, 0.0L, -2.48811461997166764192642586468L,
     -5.90290826836842996371446475743e-1L, 2.12300514481811942347288949897e1L,
     1.52792336328824235832596922938e1L, -3.32882109689848629194453265587e1L,
     -2.03312017085086261358222928593e-2L},
    {-9.3714243008598732571704021658e-1L, 0.0L, 0.0L, 5.18637242884406370830023853209L,
     1.09143734899672957818500254654L, -8.14978701074692612513997267357L,
     -1.85200656599969598641566180701e1L, 2.27394870993505042818970056734e1L,
     2.49360555267965238987089396762L, -3.0467644718982195003823669022L},
    {2.27331014751653820792359768449L, 0.0L, 0.0L, -1.05344954667372501984066689879e1L,
     -2.00087205822486249909675718444L, -1.79589318631187989172765950534e1L,
     2.79488845294199600508499808837e1L, -2.85899827713502369474065508674L,
     -8.87285693353062954433549289258L, 1.23605671757943030647266201528e1L,
     6.43392746015763530355970484046e-1L},
    // Row 12: the eighth-order weights b (y_new = x + h sum b_j k_j; b_1..b_4 = 0).
    {5.42937341165687622380535766363e-2L, 0.0L, 0.0L, 0.0L, 0.0L, 4.45031289275240888144113950566L,
     1.89151789931450038304281599044L, -5.8012039600105847814672114227L, 3.1116436695781989440891606237e-1L,
     -1.52160949662516078556178806805e-1L, 2.01365400804030348374776537501e-1L,
     4.47106157277725905176885569043e-2L},
    {5.61675022830479523392909219681e-2L, 0.0L, 0.0L, 0.0L, 0.0L, 0.0L, 2.53500210216624811088794765333e-1L,
     -2.46239037470802489917441475441e-1L, -1.24191423263816360469010140626e-1L,
     1.5329179827876569731206322685e-1L, 8.20105229563468988491666602057e-3L,
     7.56789766054569976138603589584e-3L, -8.298e-3L},
    {3.18346481635021405060768473261e-2L, 0.0L, 0.0L, 0.0L, 0.0L, 2.83009096723667755288322961402e-2L,
     5.35419883074385676223797384372e-2L, -5.49237485713909884646569340306e-2L, 0.0L, 0.0L,
     -1.08347328697249322858509316994e-4L, 3.82571090835658412954920192323e-4L,
     -3.40465008687404560802977114492e-4L, 1.41312443674632500278074618366e-1L},
    {-4.28896301583791923408573538692e-1L, 0.0L, 0.0L, 0.0L, 0.0L, -4.69762141536116384314449447206L,
     7.68342119606259904184240953878L, 4.06898981839711007970213554331L, 3.56727187455281109270669543021e-1L,
     0.0L, 0.0L, 0.0L, -1.39902416515901462129418009734e-3L, 2.9475147891527723389556272149L,
     -9.15095847217987001081870187138L}};

// Fifth-order error estimator: err5 = h sum e5_j k_j  (dop853.f: ER1, ER6..ER12).
inline constexpr long double dop853_e5[12] = {
    0.1312004499419488073250102996e-1L, 0.0L, 0.0L, 0.0L, 0.0L, -0.1225156446376204440720569753e1L,
    -0.4957589496572501915214079952L,   0.1664377182454986536961530415e1L,
    -0.3503288487499736816886487290L,   0.3341791187130174790297318841L,
    0.8192320648511571246570742613e-1L, -0.2235530786388629525884427845e-1L};

// Third-order embedded weights bhh (on stages 0, 8 and 11; dop853.f: BHH1..BHH3); the third-order
// error estimate is err3 = h sum (b_j - bhh_j) k_j.
inline constexpr long double dop853_bhh[3] = {0.244094488188976377952755905512L, 0.733846688281611857341361741547L,
                                              0.220588235294117647058823529412e-1L};

// Dense output: the coefficients d_{4..7,j} of dop853.f (D41..D716), on all 16 stages.
inline constexpr long double dop853_d[4][16] = {
    {-0.84289382761090128651353491142e1L, 0.0L, 0.0L, 0.0L, 0.0L, 0.56671495351937776962531783590L,
     -0.30689499459498916912797304727e1L, 0.23846676565120698287728149680e1L, 0.21170345824450282767155149946e1L,
     -0.87139158377797299206789907490L, 0.22404374302607882758541771650e1L, 0.63157877876946881815570249290L,
     -0.88990336451333310820698117400e-1L, 0.18148505520854727256656404962e2L,
     -0.91946323924783554000451984436e1L, -0.44360363875948939664310572000e1L},
    {0.10427508642579134603413151009e2L, 0.0L, 0.0L, 0.0L, 0.0L, 0.24228349177525818288430175319e3L,
     0.16520045171727028198505394887e3L, -0.37454675472269020279518312152e3L,
     -0.22113666853125306036270938578e2L, 0.77334326684722638389603898808e1L,
     -0.30674084731089398182061213626e2L, -0.93321305264302278729567221706e1L,
     0.15697238121770843886131091075e2L, -0.31139403219565177677282850411e2L,
     -0.93529243588444783865713862664e1L, 0.35816841486394083752465898540e2L},
    {0.19985053242002433820987653617e2L, 0.0L, 0.0L, 0.0L, 0.0L, -0.38703730874935176555105901742e3L,
     -0.18917813819516756882830838328e3L, 0.52780815920542364900561016686e3L,
     -0.11573902539959630126141871134e2L, 0.68812326946963000169666922661e1L,
     -0.10006050966910838403183860980e1L, 0.77771377980534432092869265740L,
     -0.27782057523535084065932004339e1L, -0.60196695231264120758267380846e2L,
     0.84320405506677161018159903784e2L, 0.11992291136182789328035130030e2L},
    {-0.25693933462703749003312586129e2L, 0.0L, 0.0L, 0.0L, 0.0L, -0.15418974869023643374053993627e3L,
     -0.23152937917604549567536039109e3L, 0.35763911791061412378285349910e3L,
     0.93405324183624310003907691704e2L, -0.37458323136451633156875139351e2L,
     0.10409964950896230045147246184e3L, 0.29840293426660503123344363579e2L,
     -0.43533456590011143754432175058e2L, 0.96324553959188282948394950600e2L,
     -0.39177261675615439165231486172e2L, -0.14972683625798562581422125276e3L}};

}  // namespace detail

// The DOP853 coefficients rounded once to S.
template <class S>
struct Dop853Tableau {
  static constexpr int stages = 12, dense_stages = 16;

  static constexpr std::array<S, 16> c = [] {
    std::array<S, 16> r{};
    for (int i = 0; i < 16; ++i) r[i] = S(detail::dop853_c[i]);
    return r;
  }();
  static constexpr std::array<std::array<S, 16>, 16> a = [] {
    std::array<std::array<S, 16>, 16> r{};
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) r[i][j] = S(detail::dop853_a[i][j]);
    return r;
  }();
  // b_j = a[12][j].
  static constexpr std::array<S, 12> e5 = [] {
    std::array<S, 12> r{};
    for (int j = 0; j < 12; ++j) r[j] = S(detail::dop853_e5[j]);
    return r;
  }();
  static constexpr std::array<S, 12> e3 = [] {
    std::array<S, 12> r{};
    for (int j = 0; j < 12; ++j) r[j] = S(detail::dop853_a[12][j]);
    r[0] = S(detail::dop853_a[12][0] - detail::dop853_bhh[0]);
    r[8] = S(detail::dop853_a[12][8] - detail::dop853_bhh[1]);
    r[11] = S(detail::dop853_a[12][11] - detail::dop853_bhh[2]);
    return r;
  }();
  static constexpr std::array<std::array<S, 16>, 4> d = [] {
    std::array<std::array<S, 16>, 4> r{};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 16; ++j) r[i][j] = S(detail::dop853_d[i][j]);
    return r;
  }();
};

// Same interface as Dopri5 (prepare, try_step, do_step, calc_state, ...), so a driver templated
// on the stepper can use either.
template <class S>
class Dop853 {
 public:
  using value_type = S;
  using Settings = typename StepAdjuster<S>::Settings;
  // error_order is the exponent the controller uses, err ~ h^(error_order+1) = h^8 as in dop853.f
  // (the combined estimate below behaves like h^8 for small h, see try_step).
  static constexpr int order = 8, error_order = 7;

  // The controller constants of dop853.f: safety 0.9, the step may shrink to 0.333 and grow to 6
  // times per attempt, no PI term (BETA = 0).
  static Settings default_settings() {
    Settings s;
    s.safety = S(0.9);
    s.fac_min = S(0.333);
    s.fac_max = S(6);
    s.beta = S(0);
    return s;
  }

  // dense_output = false skips the three extra stages per accepted step (then calc_state throws);
  // the stepper then costs 12 system calls per accepted and 11 per rejected step.
  explicit Dop853(Settings settings = default_settings(), bool dense_output = true)
      : adjuster_(error_order, settings), dense_enabled_(dense_output) {}

  // Makes k1 = f(t, x) available and returns it; reuses the FSAL derivative only when (t, x) is
  // exactly the end point of the last step (as Dopri5::prepare).
  template <class Sys>
    requires System<Sys, S>
  const State<S>& prepare(Sys& sys, const State<S>& x, S t) {
    if (!(k1_valid_ && t == t_k1_ && x == x_k1_)) {
      resize(x.size());
      sys(t, x, k_[0]);
      ++rhs_evals_;
      x_k1_ = x;
      t_k1_ = t;
      k1_valid_ = true;
    }
    return k_[0];
  }

  // One controlled attempt from (t, x) with step h (either sign); same contract as
  // Dopri5::try_step. Error norm as in dop853.f ([HNW] II.5, (5.5)-(5.6)): with the RMS norms
  // n5 = ||err5 / sc||, n3 = ||err3 / sc|| (sc_i = atol + rtol max(|x_i|, |y_new_i|)),
  //   err = n5^2 / sqrt(n5^2 + 0.01 n3^2),
  // which is ~ n5^2 / (0.1 n3) = O(h^6 * h^6 / h^4) = O(h^8) for small h and ~ n5 for large h.
  template <class Sys>
    requires System<Sys, S>
  bool try_step(Sys& sys, State<S>& x, S& t, S& h, const Tolerances& tol) {
    using std::isfinite;
    using std::sqrt;
    if (h == S(0)) throw std::invalid_argument("Dop853::try_step: zero step size");
    prepare(sys, x, t);
    stages(sys, x, t, h);
    using T = Dop853Tableau<S>;
    const std::size_t n = x.size();
    for (std::size_t i = 0; i < n; ++i) {
      S s5 = 0, s3 = 0;
      for (int j = 0; j < T::stages; ++j) {
        s5 += T::e5[j] * k_[j][i];
        s3 += T::e3[j] * k_[j][i];
      }
      err5_[i] = h * s5;
      err3_[i] = h * s3;
    }
    const ErrorChecker<S> checker(tol);
    const S n5 = checker.norm(err5_, x, ynew_), n3 = checker.norm(err3_, x, ynew_);
    // Written as n5 / sqrt(1 + 0.01 (n3/n5)^2) so that large norms do not overflow; NaN or Inf in
    // either estimate makes the error non-finite (rejection with the largest reduction).
    if (!isfinite(n5) || !isfinite(n3)) {
      last_error_ = std::numeric_limits<S>::infinity();
    } else if (n5 == S(0)) {
      last_error_ = S(0);
    } else {
      const S q = n3 / n5;
      last_error_ = n5 / sqrt(S(1) + S(0.01) * q * q);
    }
    if (isfinite(last_error_) && last_error_ <= S(1)) {
      non_finite_component_ = IntegrationError::no_component;
      accept(sys, x, t, h);
      t = t_new_;
      h *= adjuster_.accepted(last_error_);
      return true;
    }
    non_finite_component_ = isfinite(last_error_) ? IntegrationError::no_component : locate_non_finite();
    h *= adjuster_.rejected(last_error_);
    return false;
  }

  // A plain step of the eighth-order method, no error control (fixed-step use, order tests).
  // Updates the FSAL derivative and the dense output like an accepted step.
  template <class Sys>
    requires System<Sys, S>
  void do_step(Sys& sys, State<S>& x, S t, S h) {
    prepare(sys, x, t);
    stages(sys, x, t, h);
    accept(sys, x, t, h);
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
  const State<S>& derivative() const { return k_[0]; }
  S last_error() const { return last_error_; }
  std::size_t last_non_finite_component() const { return non_finite_component_; }
  bool has_dense_output() const { return dense_valid_; }
  bool dense_output_enabled() const { return dense_enabled_; }
  std::size_t rhs_evals() const { return rhs_evals_; }
  StepAdjuster<S>& adjuster() { return adjuster_; }

  void reset() {
    k1_valid_ = false;
    dense_valid_ = false;
    adjuster_.reset();
    non_finite_component_ = IntegrationError::no_component;
  }

 private:
  // y = x + h * sum_{j < row-length} a[row][j] k_j.
  void combine(State<S>& y, const State<S>& x, S h, int row, int upto) const {
    using T = Dop853Tableau<S>;
    for (std::size_t i = 0; i < x.size(); ++i) {
      S acc = 0;
      for (int j = 0; j < upto; ++j) acc += T::a[row][j] * k_[j][i];
      y[i] = x[i] + h * acc;
    }
  }

  // Stages 1..11 from (t, x) with step h; leaves the eighth-order solution in ynew_.
  template <class Sys>
  void stages(Sys& sys, const State<S>& x, S t, S h) {
    using T = Dop853Tableau<S>;
    const State<S>& y = y_;
    for (int s = 1; s < T::stages; ++s) {
      combine(y_, x, h, s, s);
      sys(s == T::stages - 1 ? t + h : t + T::c[s] * h, y, k_[s]);
    }
    rhs_evals_ += T::stages - 1;
    combine(ynew_, x, h, T::stages, T::stages);
  }

  // Commits the step (t, x) -> (t+h, ynew_): FSAL stage f(t+h, ynew_), dense-output coefficients
  // (three more stages when enabled), x.
  template <class Sys>
  void accept(Sys& sys, State<S>& x, S t, S h) {
    using T = Dop853Tableau<S>;
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
    x_k1_ = x;
    t_k1_ = t_new_;
  }

  std::size_t locate_non_finite() const {
    for (int s = 1; s < Dop853Tableau<S>::stages; ++s) {
      const std::size_t i = first_non_finite(k_[s]);
      if (i != IntegrationError::no_component) return i;
    }
    std::size_t i = first_non_finite(ynew_);
    if (i == IntegrationError::no_component) i = first_non_finite(err5_);
    if (i == IntegrationError::no_component) i = first_non_finite(err3_);
    return i;
  }

  void resize(std::size_t n) {
    if (k_[0].size() == n) return;
    for (State<S>& v : k_) v.assign(n, S(0));
    for (State<S>& v : r_) v.assign(n, S(0));
    for (State<S>* v : {&y_, &ynew_, &err5_, &err3_}) v->assign(n, S(0));
    k1_valid_ = false;
    dense_valid_ = false;
  }

  StepAdjuster<S> adjuster_;
  bool dense_enabled_;
  std::array<State<S>, 16> k_;
  State<S> y_, ynew_, err5_, err3_;
  std::array<State<S>, 8> r_;  // dense-output coefficients of the last accepted step
  State<S> x_k1_;
  S t_k1_ = S(0), t_old_ = S(0), t_new_ = S(0), h_old_ = S(0);
  S last_error_ = S(0);
  bool k1_valid_ = false, dense_valid_ = false;
  std::size_t non_finite_component_ = IntegrationError::no_component;
  std::size_t rhs_evals_ = 0;
};

}  // namespace eomc::runtime
