# Empty dependencies file for eomc_generator.
# This may be replaced when dependencies are built.
