file(REMOVE_RECURSE
  "libeomc_generator.a"
)
