// Siconos 4.4 on the contact bench's two systems (see bench/contact_siconos.cpp). C++17: Siconos'
// headers do not compile as C++20.
#include "contact_siconos_peer.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <SiconosKernel.hpp>

namespace contact_bench {

namespace {

// --- Siconos --------------------------------------------------------------------------------------

// Housner's block in Siconos' form M θ̈ + F_int = p, M = I0 = (4/3) m R², F_int = m g R sin(α − θ).
namespace block {
constexpr double m = 1, g = 9.81, b = 0.2, h = 0.6;
const double R = std::sqrt(b * b + h * h), alpha = std::atan(b / h);
void f_int(double, unsigned int, double* q, double*, double* out, unsigned int, double*) {
    out[0] = m * g * R * std::sin(alpha - q[0]);
}
void f_int_q(double, unsigned int, double* q, double*, double* out, unsigned int, double*) {
    out[0] = -m * g * R * std::cos(alpha - q[0]);
}
void f_int_v(double, unsigned int, double*, double*, double* out, unsigned int, double*) { out[0] = 0; }
}  // namespace block

struct SiconosModel {
    SP::NonSmoothDynamicalSystem nsds;
    SP::LagrangianDS ds;
};

SiconosModel siconos_model(bool is_block) {
    SiconosModel out;
    SP::SiconosVector q0(new SiconosVector(1)), v0(new SiconosVector(1));
    SP::SiconosMatrix M(new SimpleMatrix(1, 1));
    double e;
    if (!is_block) {
        const double m = 1, g = 9.81;
        (*q0)(0) = 2.0, (*v0)(0) = 0.0, (*M)(0, 0) = m, e = 0.7;
        SP::LagrangianLinearTIDS ball(new LagrangianLinearTIDS(q0, v0, M));
        SP::SiconosVector weight(new SiconosVector(1));
        (*weight)(0) = -m * g;
        ball->setFExtPtr(weight);
        out.ds = ball;
    } else {
        using namespace block;
        (*q0)(0) = alpha / 2, (*v0)(0) = 0.0, (*M)(0, 0) = 4.0 / 3.0 * m * R * R;
        e = 1 - 1.5 * std::pow(std::sin(alpha), 2);
        SP::LagrangianDS ds(new LagrangianDS(q0, v0, M));
        ds->setComputeFIntFunction(f_int);
        ds->setComputeJacobianFIntqFunction(f_int_q);
        ds->setComputeJacobianFIntqDotFunction(f_int_v);
        out.ds = ds;
    }
    SP::SimpleMatrix H(new SimpleMatrix(1, 1));
    (*H)(0, 0) = 1.0;
    SP::NonSmoothLaw law(new NewtonImpactNSL(e));
    SP::Relation relation(new LagrangianLinearTIR(H));
    SP::Interaction inter(new Interaction(law, relation));
    out.nsds.reset(new NonSmoothDynamicalSystem(0.0, 5.0));
    out.nsds->insertDynamicalSystem(out.ds);
    out.nsds->link(inter, out.ds);
    return out;
}

}  // namespace

void siconos_event_driven(bool is_block, double rtol, Run& run) {
    SiconosModel model = siconos_model(is_block);
    SP::LsodarOSI osi(new LsodarOSI());
    osi->setTol(1, rtol, rtol * 1e-2);
    // Output events at t = 1, 2, …: t = 1 is one of them.
    SP::TimeDiscretisation td(new TimeDiscretisation(0.0, 1.0));
    SP::EventDriven s(new EventDriven(model.nsds, td));
    s->insertIntegrator(osi);
    SP::OneStepNSProblem impact(new LCP()), acceleration(new LCP());
    s->insertNonSmoothProblem(impact, SICONOS_OSNSP_ED_IMPACT);
    s->insertNonSmoothProblem(acceleration, SICONOS_OSNSP_ED_SMOOTH_ACC);
    SP::EventsManager events = s->eventsManager();
    SP::SiconosVector q = model.ds->q(), v = model.ds->velocity();
    long count = 0;
    try {
        while (s->hasNextEvent()) {
            s->advanceToEvent();
            const bool nonsmooth = events->nextEvent()->getType() == NS_EVENT;
            s->processEvents();
            if (++count > 1000000) throw std::runtime_error("more than 10^6 events");
            run.last_step_count = double(count);
            const double t = s->startingTime();
            if (nonsmooth) run.impacts.push_back(t);
            if (std::abs(t - 1.0) < 1e-12) run.q1 = (*q)(0), run.v1 = (*v)(0);
        }
    } catch (const Siconos::exception& e) {
        // Siconos' exceptions carry their text as boost::error_info, not in what().
        const std::string* text = boost::get_error_info<Siconos::exception::extra_message>(e);
        char buf[200];
        std::snprintf(buf, sizeof buf, "throws after %zu nonsmooth events (the last at %.15g)", run.impacts.size(),
                      run.impacts.empty() ? NAN : run.impacts.back());
        run.zeno = buf;
        throw std::runtime_error(text ? *text : std::string("Siconos::exception"));
    }
    run.q5 = (*q)(0), run.v5 = (*v)(0);
    SP::SiconosVector p2 = model.ds->p(2);
    run.lambda5 = p2 ? (*p2)(0) : NAN;
    run.last_step_count = double(count);
    char buf[160];
    std::snprintf(buf, sizeof buf, "%zu nonsmooth events, the last at %.15g; %s at t = 5", run.impacts.size(),
                  run.impacts.empty() ? NAN : run.impacts.back(),
                  std::abs((*q)(0)) < 1e-6 && std::abs((*v)(0)) < 1e-6 ? "at rest" : "not at rest");
    run.zeno = buf;
}

void siconos_moreau_jean(bool is_block, double h, Run& run) {
    SiconosModel model = siconos_model(is_block);
    const long n = long(std::ceil(5.0 / h - 1e-9));
    const double dt = 5.0 / double(n);
    SP::MoreauJeanOSI osi(new MoreauJeanOSI(0.5));
    SP::TimeDiscretisation td(new TimeDiscretisation(0.0, dt));
    SP::OneStepNSProblem lcp(new LCP());
    SP::TimeStepping s(new TimeStepping(model.nsds, td, osi, lcp));
    SP::SiconosVector q = model.ds->q(), v = model.ds->velocity();
    double last_p = 0, p_end = 0;
    long k = 0;
    const long k1 = long(std::llround(1.0 / dt));
    while (s->hasNextEvent()) {
        s->computeOneStep();
        ++k;
        const double p = (*model.ds->p(1))(0);
        if (p > 0 && !(last_p > 0)) run.impacts.push_back(double(k) * dt);
        last_p = p_end = p;
        if (k == k1) run.q1 = (*q)(0), run.v1 = (*v)(0);
        s->nextStep();
    }
    run.q5 = (*q)(0), run.v5 = (*v)(0), run.lambda5 = p_end / dt;
    run.last_step_count = double(k);
    run.zeno = "passes (time stepping)";
}

}  // namespace contact_bench
