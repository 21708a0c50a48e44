
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/main/src/core/contact/rigid_surface.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/contact/rigid_surface.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/contact/rigid_surface.cpp.o.d"
  "/work/main/src/core/drape/drape_problem.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/drape/drape_problem.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/drape/drape_problem.cpp.o.d"
  "/work/main/src/core/fem_shell/director_frame.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/director_frame.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/director_frame.cpp.o.d"
  "/work/main/src/core/fem_shell/fem_shell_solver.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/fem_shell_solver.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/fem_shell_solver.cpp.o.d"
  "/work/main/src/core/fem_shell/shell_element.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/shell_element.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/shell_element.cpp.o.d"
  "/work/main/src/core/fem_shell/shell_model.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/shell_model.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/fem_shell/shell_model.cpp.o.d"
  "/work/main/src/core/io/collider_spec.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/collider_spec.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/collider_spec.cpp.o.d"
  "/work/main/src/core/io/drape_plots.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/drape_plots.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/drape_plots.cpp.o.d"
  "/work/main/src/core/io/drape_report.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/drape_report.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/drape_report.cpp.o.d"
  "/work/main/src/core/io/gnuplot.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/gnuplot.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/gnuplot.cpp.o.d"
  "/work/main/src/core/io/material_presets.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/material_presets.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/material_presets.cpp.o.d"
  "/work/main/src/core/io/mesh_reader.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/mesh_reader.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/mesh_reader.cpp.o.d"
  "/work/main/src/core/io/mesh_writer.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/mesh_writer.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/mesh_writer.cpp.o.d"
  "/work/main/src/core/io/scene.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/scene.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/io/scene.cpp.o.d"
  "/work/main/src/core/material/shell_material.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/material/shell_material.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/material/shell_material.cpp.o.d"
  "/work/main/src/core/mesh/grid_generators.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/grid_generators.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/grid_generators.cpp.o.d"
  "/work/main/src/core/mesh/mesh_check.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/mesh_check.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/mesh_check.cpp.o.d"
  "/work/main/src/core/mesh/mesh_weld.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/mesh_weld.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/mesh_weld.cpp.o.d"
  "/work/main/src/core/mesh/vertex_selection.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/vertex_selection.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/mesh/vertex_selection.cpp.o.d"
  "/work/main/src/core/particle/particle_contact.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_contact.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_contact.cpp.o.d"
  "/work/main/src/core/particle/particle_dynamics.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_dynamics.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_dynamics.cpp.o.d"
  "/work/main/src/core/particle/particle_loads.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_loads.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_loads.cpp.o.d"
  "/work/main/src/core/particle/particle_network.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_network.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_network.cpp.o.d"
  "/work/main/src/core/particle/particle_seams.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_seams.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_seams.cpp.o.d"
  "/work/main/src/core/particle/particle_static_solver.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_static_solver.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/particle/particle_static_solver.cpp.o.d"
  "/work/main/src/core/solver/arc_length_solver.cpp" "CMakeFiles/cloth_hair_sim_core.dir/src/core/solver/arc_length_solver.cpp.o" "gcc" "CMakeFiles/cloth_hair_sim_core.dir/src/core/solver/arc_length_solver.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
