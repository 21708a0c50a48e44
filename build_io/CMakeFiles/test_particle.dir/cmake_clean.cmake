file(REMOVE_RECURSE
  "CMakeFiles/test_particle.dir/test/test_particle.cpp.o"
  "CMakeFiles/test_particle.dir/test/test_particle.cpp.o.d"
  "devel/lib/cloth_hair_sim/test_particle"
  "devel/lib/cloth_hair_sim/test_particle.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_particle.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
