# Empty compiler generated dependencies file for test_drape_tool.
# This may be replaced when dependencies are built.
