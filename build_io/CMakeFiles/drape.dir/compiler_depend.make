# Empty compiler generated dependencies file for drape.
# This may be replaced when dependencies are built.
