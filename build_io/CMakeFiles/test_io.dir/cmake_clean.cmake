file(REMOVE_RECURSE
  "CMakeFiles/test_io.dir/test/test_io.cpp.o"
  "CMakeFiles/test_io.dir/test/test_io.cpp.o.d"
  "devel/lib/cloth_hair_sim/test_io"
  "devel/lib/cloth_hair_sim/test_io.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_io.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
