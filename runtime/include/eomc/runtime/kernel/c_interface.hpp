#pragma once

// The C interface of a compiled kernel: what templates/kernel_adapter.cpp, compiled with one
// generated kernel into a shared object, exports to the process that loads it (eomc's host,
// generator/host/kernel_loader.cpp):
//
//   extern "C" int eomc_adapter_abi();                     kernel_c::abi, checked first
//   extern "C" const char* eomc_kernel_identity();         which kernel, checked next
//   extern "C" const kernel_c::VTable* eomc_kernel_vtable();
//
// Functions over double, with the kernel's Parameters behind a const void*, so that the loader
// needs no knowledge of the kernel's C++ types; parameters travel by position in
// parameter_names order, never by member name.

namespace eomc::runtime::kernel_c {

// Bumped whenever the exports above or VTable's fixed part change; its block rows are checked by
// their text (block_table), so a new row of blocks.def needs no bump.
inline constexpr int abi = 16;  // 3: acceleration and events; 4: project; 5: variational_rhs;
                                // 6: project(t, x, p); 7: eomc_kernel_identity; 8: constraint rows;
                                // 9: singular sets; 10: the mechanical form and unilateral rows;
                                // 11: programs; 12: constraint_rows; 13: contact_time_rates;
                                // 14: the batched rhs and invariants; 15: jacobian;
                                // 16: one vtable, its blocks from blocks.def

// The C signatures of a kernel's functions ("shapes"), spelled out for a parameters type Params
// (const void* here, the loader's Parameters handle in its accessors), and the call of a function
// of that shape with `params` for p.
#define EOMC_KERNEL_SHAPE_rates(Params) double t, const double* x, double* out, Params p
#define EOMC_KERNEL_CALL_rates(params) t, x, out, params
#define EOMC_KERNEL_SHAPE_in_place(Params) double t, double* x, Params p
#define EOMC_KERNEL_CALL_in_place(params) t, x, params
#define EOMC_KERNEL_SHAPE_from_parameters(Params) Params p, double* out
#define EOMC_KERNEL_CALL_from_parameters(params) params, out
#define EOMC_KERNEL_SHAPE_bilateral_rows(Params) \
  double t, const double* x, double* out, double* phi, double* W, double* r, Params p
#define EOMC_KERNEL_CALL_bilateral_rows(params) t, x, out, phi, W, r, params

// blocks.def as text: a library built with another table has another VTable.
inline constexpr char block_table[] =
#define EOMC_KERNEL_ROWS(...) "rows " #__VA_ARGS__ "\n"
#define EOMC_KERNEL_COLUMN(...) "column " #__VA_ARGS__ "\n"
#define EOMC_KERNEL_FUNCTION(...) "function " #__VA_ARGS__ "\n"
#define EOMC_KERNEL_FUNCTION_OR_ZEROS(...) "function or zeros " #__VA_ARGS__ "\n"
#include "eomc/runtime/kernel/blocks.def"
    "";

struct VTable {
  const char* blocks;  // block_table as the library was built: first, so that it is read before the rest

  const char* scene_name;
  int n_state, n_parameters, n_invariants, n_outputs;
  const char* const* state_names;
  const char* const* parameter_names;
  const char* const* invariant_names;
  const char* const* output_names;
  const double* initial_state;
  const double* parameter_defaults;  // n_parameters: the scene's
  void* (*create_parameters)(const double* values);  // from n_parameters values
  void (*destroy_parameters)(void* p);
  void (*rhs)(EOMC_KERNEL_SHAPE_rates(const void*));
  void (*invariants)(EOMC_KERNEL_SHAPE_rates(const void*));
  void (*outputs)(EOMC_KERNEL_SHAPE_rates(const void*));

  // The mechanical form M u̇ = f of the velocity block x[velocity_offset .. + n_velocities).
  int n_coordinates, velocity_offset, n_velocities;
  void (*mass_matrix)(EOMC_KERNEL_SHAPE_rates(const void*));
  void (*forcing)(EOMC_KERNEL_SHAPE_rates(const void*));

  // Batchable kernels: batch_width members per call, arrays lane-minor (0 lanes: not batchable).
  int batch_width;
  void* (*create_batch_parameters)(const double* values);  // n_parameters × batch_width, lane-minor
  void (*destroy_batch_parameters)(void* p);
  void (*rhs_batch)(EOMC_KERNEL_SHAPE_rates(const void*));
  void (*invariants_batch)(EOMC_KERNEL_SHAPE_rates(const void*));

  // The optional blocks: a count and arrays per group of rows, a flag and a function per function.
#define EOMC_KERNEL_ROWS(concept, count, names) \
  int count;                                    \
  const char* const* names;
#define EOMC_KERNEL_COLUMN(concept, count, column, type, width) const type* column;
#define EOMC_KERNEL_FUNCTION(concept, name, shape) \
  bool has_##name;                                 \
  void (*name)(EOMC_KERNEL_SHAPE_##shape(const void*));
#include "eomc/runtime/kernel/blocks.def"
};

}  // namespace eomc::runtime::kernel_c
