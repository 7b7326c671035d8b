file(REMOVE_RECURSE
  "CMakeFiles/eomc_generator.dir/scene/scene.cpp.o"
  "CMakeFiles/eomc_generator.dir/scene/scene.cpp.o.d"
  "CMakeFiles/eomc_generator.dir/support/diagnostic.cpp.o"
  "CMakeFiles/eomc_generator.dir/support/diagnostic.cpp.o.d"
  "libeomc_generator.a"
  "libeomc_generator.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/eomc_generator.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
