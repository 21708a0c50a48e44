file(REMOVE_RECURSE
  "CMakeFiles/drape.dir/src/tools/drape_main.cpp.o"
  "CMakeFiles/drape.dir/src/tools/drape_main.cpp.o.d"
  "devel/lib/cloth_hair_sim/drape"
  "devel/lib/cloth_hair_sim/drape.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/drape.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
