file(REMOVE_RECURSE
  "CMakeFiles/test_fem_shell.dir/test/test_fem_shell.cpp.o"
  "CMakeFiles/test_fem_shell.dir/test/test_fem_shell.cpp.o.d"
  "devel/lib/cloth_hair_sim/test_fem_shell"
  "devel/lib/cloth_hair_sim/test_fem_shell.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_fem_shell.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
