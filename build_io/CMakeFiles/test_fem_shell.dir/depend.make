# Empty dependencies file for test_fem_shell.
# This may be replaced when dependencies are built.
