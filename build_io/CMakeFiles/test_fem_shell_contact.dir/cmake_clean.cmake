file(REMOVE_RECURSE
  "CMakeFiles/test_fem_shell_contact.dir/test/test_fem_shell_contact.cpp.o"
  "CMakeFiles/test_fem_shell_contact.dir/test/test_fem_shell_contact.cpp.o.d"
  "devel/lib/cloth_hair_sim/test_fem_shell_contact"
  "devel/lib/cloth_hair_sim/test_fem_shell_contact.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_fem_shell_contact.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
