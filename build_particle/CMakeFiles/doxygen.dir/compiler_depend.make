# Empty custom commands generated dependencies file for doxygen.
# This may be replaced when dependencies are built.
