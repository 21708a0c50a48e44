# Empty dependencies file for cloth_hair_sim_core.
# This may be replaced when dependencies are built.
