#pragma once

// Version of the eomc runtime's interface. Generated kernels static_assert against it, so a
// kernel emitted for an older runtime fails at compile time instead of misbehaving at run time.
// Bump it whenever a signature that generated code or the CLI relies on changes.
#define EOMC_RUNTIME_VERSION 1
