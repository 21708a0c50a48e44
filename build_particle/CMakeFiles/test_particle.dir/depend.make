# Empty dependencies file for test_particle.
# This may be replaced when dependencies are built.
