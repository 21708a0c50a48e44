# Empty dependencies file for test_fem_shell_contact.
# This may be replaced when dependencies are built.
