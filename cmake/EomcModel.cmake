# eomc_add_model(<target> SCENES <scene.toml>... [JACOBIAN] [EOMC <eomc executable>] [OPTIONS <generate flags>...])
#
# Generates one kernel header per scene at build time (never at configure time, so the
# headers cannot go stale) into <build>/eomc_models/, and makes <target> an INTERFACE
# library whose users can `#include "<scene name>.hpp"`. Each header depends on its scene,
# on the generator and on the kernel template, so editing any of them regenerates it.
#
# The header is named after the scene's [scene] name, which is read here from the file
# (with _NAME appended for OPTIONS --orbit-formulation NAME, as eomc names it).
# OPTIONS go to `eomc generate` as they are (e.g. --hamiltonian, --variational). JACOBIAN adds
# jacobian() (∂ẋ/∂x) to every kernel (`eomc generate --jacobian`), for implicit methods or error
# propagation; without it a kernel has one only if its scene says [kernel] jacobian = true.
set(EOMC_CMAKE_DIR "${CMAKE_CURRENT_LIST_DIR}")

function(eomc_add_model target)
  cmake_parse_arguments(ARG "JACOBIAN" "EOMC" "SCENES;OPTIONS" ${ARGN})
  if(ARG_JACOBIAN)
    list(APPEND ARG_OPTIONS --jacobian)
  endif()
  if(NOT ARG_SCENES)
    message(FATAL_ERROR "eomc_add_model(${target}): no SCENES given")
  endif()
  if(ARG_EOMC)
    set(generator "${ARG_EOMC}")
    set(generator_dependency "${ARG_EOMC}")
  elseif(TARGET eomc)
    set(generator "$<TARGET_FILE:eomc>")
    set(generator_dependency eomc)
  else()
    message(FATAL_ERROR "eomc_add_model(${target}): no eomc target; pass EOMC <path to the eomc executable>")
  endif()

  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/eomc_models")
  set(template "${EOMC_CMAKE_DIR}/../templates/kernel.hpp.in")
  set(headers "")
  foreach(scene IN LISTS ARG_SCENES)
    get_filename_component(scene "${scene}" ABSOLUTE)
    file(STRINGS "${scene}" name_line REGEX "^[ \t]*name[ \t]*=[ \t]*\"[a-z][a-z0-9_]*\"" LIMIT_COUNT 1)
    if(NOT name_line MATCHES "\"([a-z][a-z0-9_]*)\"")
      message(FATAL_ERROR "eomc_add_model(${target}): ${scene} has no [scene] name = \"...\"")
    endif()
    set(header_name "${CMAKE_MATCH_1}")
    # --orbit-formulation NAME appends _NAME to the kernel's name (scene::set_orbit_formulation).
    list(FIND ARG_OPTIONS "--orbit-formulation" formulation_flag)
    if(formulation_flag GREATER -1)
      math(EXPR formulation_index "${formulation_flag} + 1")
      list(GET ARG_OPTIONS ${formulation_index} formulation)
      set(header_name "${header_name}_${formulation}")
    endif()
    # So does --rigid-formulation NAME (scene::set_rigid_formulation).
    list(FIND ARG_OPTIONS "--rigid-formulation" rigid_flag)
    if(rigid_flag GREATER -1)
      math(EXPR rigid_index "${rigid_flag} + 1")
      list(GET ARG_OPTIONS ${rigid_index} rigid_formulation)
      set(header_name "${header_name}_${rigid_formulation}")
    endif()
    set(header "${out_dir}/${header_name}.hpp")
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${scene}")
    add_custom_command(
      OUTPUT "${header}"
      COMMAND "${generator}" generate "${scene}" -o "${out_dir}" ${ARG_OPTIONS}
      DEPENDS "${scene}" ${generator_dependency} "${template}"
      COMMENT "eomc: generating ${header_name}.hpp"
      VERBATIM)
    list(APPEND headers "${header}")
  endforeach()

  add_custom_target(${target}_generate DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_generate)
  target_include_directories(${target} INTERFACE "${out_dir}")
  if(TARGET eomc_runtime)
    target_link_libraries(${target} INTERFACE eomc_runtime)
  endif()
endfunction()
