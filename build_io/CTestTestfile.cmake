# CMake generated Testfile for 
# Source directory: /work/main
# Build directory: /work/main/build_io
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
add_test(test_drape_tool "/work/main/build_io/devel/lib/cloth_hair_sim/test_drape_tool")
set_tests_properties(test_drape_tool PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;71;add_test;/work/main/CMakeLists.txt;0;")
add_test(test_fem_shell "/work/main/build_io/devel/lib/cloth_hair_sim/test_fem_shell")
set_tests_properties(test_fem_shell PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;71;add_test;/work/main/CMakeLists.txt;0;")
add_test(test_fem_shell_contact "/work/main/build_io/devel/lib/cloth_hair_sim/test_fem_shell_contact")
set_tests_properties(test_fem_shell_contact PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;71;add_test;/work/main/CMakeLists.txt;0;")
add_test(test_io "/work/main/build_io/devel/lib/cloth_hair_sim/test_io")
set_tests_properties(test_io PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;71;add_test;/work/main/CMakeLists.txt;0;")
add_test(test_mesh_check "/work/main/build_io/devel/lib/cloth_hair_sim/test_mesh_check")
set_tests_properties(test_mesh_check PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;71;add_test;/work/main/CMakeLists.txt;0;")
add_test(test_particle "/work/main/build_io/devel/lib/cloth_hair_sim/test_particle")
set_tests_properties(test_particle PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;71;add_test;/work/main/CMakeLists.txt;0;")
