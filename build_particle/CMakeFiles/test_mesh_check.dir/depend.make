# Empty dependencies file for test_mesh_check.
# This may be replaced when dependencies are built.
