file(REMOVE_RECURSE
  "CMakeFiles/test_mesh_check.dir/test/test_mesh_check.cpp.o"
  "CMakeFiles/test_mesh_check.dir/test/test_mesh_check.cpp.o.d"
  "devel/lib/cloth_hair_sim/test_mesh_check"
  "devel/lib/cloth_hair_sim/test_mesh_check.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_mesh_check.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
