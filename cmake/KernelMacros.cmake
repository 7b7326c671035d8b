# Writes OUT, a C++ header with the sorted names of every macro that the headers of a kernel,
# its loader and the benchmark driver define (generator/codegen/kernel_macro_probe.cpp), in the
# standard and in the GNU dialect. A scene name among them is renamed by the emitter.
# Run at build time: cmake -DCXX=… -DPROBE=… -DINCLUDES="dir|dir" -DOUT=… -P KernelMacros.cmake
set(include_flags "")
string(REPLACE "|" ";" INCLUDES "${INCLUDES}")
foreach(dir IN LISTS INCLUDES)
  list(APPEND include_flags "-I${dir}")
endforeach()
set(names "")
foreach(dialect c++20 gnu++20)
  execute_process(COMMAND ${CXX} -std=${dialect} -dM -E -x c++ ${include_flags} ${PROBE}
                  OUTPUT_VARIABLE defines RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "KernelMacros: the preprocessor failed on ${PROBE}:\n${err}")
  endif()
  string(REGEX MATCHALL "#define [A-Za-z_][A-Za-z0-9_]*" found "${defines}")
  foreach(d IN LISTS found)
    string(SUBSTRING "${d}" 8 -1 name)
    list(APPEND names "${name}")
  endforeach()
endforeach()
list(REMOVE_DUPLICATES names)
list(SORT names COMPARE STRING)  # byte order, as std::string_view's operator< compares
list(LENGTH names count)
set(body "")
foreach(name IN LISTS names)
  string(APPEND body "    \"${name}\"sv,\n")
endforeach()
file(WRITE "${OUT}.tmp" "// Generated at build time by cmake/KernelMacros.cmake. Do not edit.
#pragma once

#include <array>
#include <string_view>

namespace eomc::codegen {
using namespace std::string_view_literals;  // sv literals: no constexpr strlen over 10⁴ names
inline constexpr std::array<std::string_view, ${count}> kernel_macro_names{
${body}};
}  // namespace eomc::codegen
")
file(COPY_FILE "${OUT}.tmp" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.tmp")
