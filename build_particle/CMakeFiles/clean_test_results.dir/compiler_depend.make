# Empty custom commands generated dependencies file for clean_test_results.
# This may be replaced when dependencies are built.
