// The parts of the kernel header that emit_header (cpp_emitter.cpp) fills templates/kernel.hpp.in
// with, one file for each part that is a unit of the kernel, and the text they are all made of.
// Private to codegen/: the stage's interface is cpp_emitter.hpp.
//
//   emit_function_body.cpp      scene names as C++ names, one function's body, lists, the banner's rows
//   emit_split_function.cpp     a function past operations_per_part emitted in parts (the Jacobian)
//   emit_rates.cpp              rhs() and jacobian() through M u̇ = f: closed form, straight line, Eigen
//   emit_constraints.cpp        bilateral rows: their solve, residuals and project()
//   emit_programs.cpp           programs realised by controls (Mei ch. 3)
//   emit_events_and_contacts.cpp  events and unilateral rows
//   emit_projection.cpp         project() without rows: unit renormalisation, Encke's rectification
#pragma once

#include <cstddef>
#include <initializer_list>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "codegen/kernel_ir.hpp"
#include "codegen/solve_plan.hpp"

namespace eomc::codegen {

// C++ names for the scene's names: the same text unless it would clash.
class LocalNames {
public:
    // Parameters first: their names are the Parameters struct's members, which users set by
    // name. A state or acceleration whose name a parameter already has (Delaunay's H and a drag
    // scale height H) is bound under that name with "_" appended, like a reserved word.
    explicit LocalNames(const KernelIR& ir) {
        for (const auto& s : ir.parameters) add(s);
        for (const auto& s : ir.state) add(s);
        for (const auto& s : ir.accelerations) add(s);
    }
    const std::string& operator[](const GiNaC::ex& symbol) const { return names_.at(symbol); }

private:
    void add(const NamedSymbol& s);
    std::set<std::string> used_;
    std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names_;
};

// How one function's inputs reach its expressions.
struct Inputs {
    bool acceleration_array = false;  // acc[k] holds q̈ (the Jacobian terms)
    bool state_array = true;          // x[k] holds the state (false: the reference, a function of t alone)
    bool time_argument = true;        // t is an argument (false: the restitutions, functions of p alone)
};

// The symbols e holds, added to out.
void collect_symbols(const GiNaC::ex& e, std::set<GiNaC::ex, GiNaC::ex_is_less>& out);

std::string indent(const std::string& text, int spaces);

// The body of one function: bindings of the inputs it uses, `using std::…` for the
// functions it calls, the temporaries, then `<target>[k] = …;` for each output.
std::string function_body(const KernelIR& ir, const LocalNames& names, const Block& block,
                          const std::vector<std::string>& targets, Inputs inputs = {});

std::vector<std::string> indexed(const std::string& array, std::size_t count, std::size_t offset = 0);

// The entries of several arrays, one after the other: one function's outputs.
std::vector<std::string> indexed_arrays(std::initializer_list<std::pair<const char*, std::size_t>> arrays);

// A function body for a block whose output array may be left unused.
std::string block_body(const KernelIR& ir, const LocalNames& names, const Block& block, const std::string& array,
                       Inputs inputs = {});

// A private function's body, and the parts it calls when it is too large for one
// (operations_per_part, emit_split_function.cpp). The parts are `name` + "part<k>_" with the same
// `parameters`, called with `arguments`; `arrays` are the output arrays among the parameters (a
// part writing none of one voids it).
struct SplitBody {
    std::string body;   // the function's body
    std::string parts;  // the parts' definitions, for the private section ("" when not split)
};
SplitBody split_function(const KernelIR& ir, const LocalNames& names, const Block& block,
                         const std::vector<std::string>& targets, Inputs inputs, const std::string& name,
                         const std::string& parameters, const std::string& arguments,
                         const std::vector<std::string>& arrays);

// Names as string literals: identifiers only, so that nothing needs escaping.
std::string quoted_list(const std::vector<std::string>& items, std::string_view what);

// Labels (Santilli's "S1(x,y)") as escaped string literals.
std::string literal_list(const std::vector<std::string>& items);

std::string number_list(const std::vector<double>& values, std::string_view what);

// One row of the banner's operation table.
std::string table_row(const char* name, const Block& b);

// A comment block: each line of `text` behind "// ", words made inert (comment_text).
std::string comment(const std::string& text, std::size_t width = 92);

// ---------------------------------------------------------------------------------------
// The parts

// rhs() and jacobian(): in closed form, or through M u̇ = f solved at run time, with the private
// helpers that path needs.
struct Rates {
    std::string rhs, jacobian, private_part, includes, table;
};

Rates emit_rates(const KernelIR& ir, const LocalNames& names);
// Where the rates given in closed form land: dxdt[i] in rhs, and row i of the Jacobian (n_state
// entries from out[i n_state]).
std::pair<std::vector<std::string>, std::vector<std::string>> explicit_rate_targets(const KernelIR& ir);
// explicit_rates_'s body in a kernel with rows, whose rates given in closed form may be none.
std::string explicit_rates_body(const KernelIR& ir, const LocalNames& names);
// jacobian() of a kernel whose rates go `through` a solve at run time: central differences of rhs.
std::string differenced_jacobian(std::string_view through);
// rhs() and jacobian() of a kernel with constraint rows: u̇ and λ from the Schur complement, in
// straight-line code or by runtime/constraints.hpp; ∂ẋ/∂x by central differences of rhs.
Rates emit_constrained_rates(const KernelIR& ir, const LocalNames& names);
// rhs() and jacobian() of a kernel with programs (Mei ch. 3): u̇, λ and Q_c = D λ from M u̇ = f + D λ,
// Ā u̇ = c (runtime/program/control.hpp; Udwadia–Kalaba for dependent ideal programs), ∂ẋ/∂x by
// central differences of rhs.
Rates emit_controlled_rates(const KernelIR& ir, const LocalNames& names);

// Whether a kernel's constraint rows are solved in straight-line code (codegen/solve_plan.hpp,
// plan_saddle_point) rather than by the runtime's Schur complement on Eigen.
bool straight_line_constraints(const KernelIR& ir);

// Whether a kernel's programs are reduced in straight-line code (codegen/solve_plan.hpp,
// reduce_programs) rather than solved on Eigen.
bool straight_line_programs(const KernelIR& ir);

// Only kernels with constraint rows carry them, so that no other kernel changes: the rows'
// names, their residuals and the projection after every accepted step (runtime/constraints.hpp),
// which also renormalises a unit quaternion first when the kernel has one.
std::string constraints_part(const KernelIR& ir);

// Only kernels with programs carry them: names, laws and residuals (Mei ch. 3).
std::string programs_part(const KernelIR& ir);

// Only kernels with unilateral rows carry them, so that no other kernel changes: the rows' names,
// which are kinematic, the restitution coefficients, the gaps, W and the bias (runtime/kernel.hpp,
// ContactKernel; the host builds runtime::contact::ContactSystem from them).
std::string contacts_part(const KernelIR& ir, const LocalNames& names);

// Only kernels of scenes with [events] carry them, so that no other kernel changes.
std::string events_part(const KernelIR& ir, const LocalNames& names);

// A unit quaternion's rates keep |e| = 1 only to the integrator's error; the runtime's drivers
// call project(t, x) after every accepted step when a kernel has one. The body is
// runtime::renormalise_quaternion (runtime/quaternion.hpp) written out: the bundled
// free_disk_tube_ball kernel prints it so, and tests/runtime_routines checks that the two agree.
std::string unit_renormalisation(const KernelIR& ir);

std::string unit_projection(const KernelIR& ir);

// Encke's rectification: project() calls the runtime's (runtime/orbit/encke.hpp) with the
// reference orbit the state describes, which the kernel writes as a private function.
struct Rectification {
    std::string project, private_part;
};
Rectification rectification(const KernelIR& ir, const LocalNames& names);

}  // namespace eomc::codegen
