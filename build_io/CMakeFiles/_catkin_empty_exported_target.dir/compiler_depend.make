# Empty custom commands generated dependencies file for _catkin_empty_exported_target.
# This may be replaced when dependencies are built.
