file(REMOVE_RECURSE
  "CMakeFiles/test_drape_tool.dir/test/test_drape_tool.cpp.o"
  "CMakeFiles/test_drape_tool.dir/test/test_drape_tool.cpp.o.d"
  "devel/lib/cloth_hair_sim/test_drape_tool"
  "devel/lib/cloth_hair_sim/test_drape_tool.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_drape_tool.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
